#include "host/core/output_set.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <system_error>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/internal_error.h"

namespace cutwork {
namespace fs = std::filesystem;

namespace {

constexpr const char* report_name = "report.json";
constexpr const char* staging_prefix = ".cutwork-staging.";
constexpr const char* journal_name = ".journal";     // in the staging folder: the names being published
constexpr const char* previous_name = ".previous";   // in the staging folder: the previous set, moved aside

OutputSet::StepHook& step_hook() {
  static OutputSet::StepHook hook;
  return hook;
}

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

std::vector<std::string> read_lines(const fs::path& p) {
  std::vector<std::string> lines;
  std::ifstream in(p);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line.find('/') == std::string::npos && line != "." && line != "..") lines.push_back(line);
  return lines;
}

std::string join_lines(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += n + "\n";
  return text;
}

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

/// A temporary of write_file_atomic (".NAME.tmpDIGITS") left by a run that died while writing.
bool is_stale_temporary(const std::string& name) {
  const auto p = name.rfind(".tmp");
  if (name.size() < 2 || name[0] != '.' || p == std::string::npos || p == 0 || p + 4 == name.size()) return false;
  return std::all_of(name.begin() + std::ptrdiff_t(p + 4), name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// Puts back the set a publication from `staging` moved aside, unless that publication got as
/// far as moving its report.json in (then the new set is complete and stays). A name of the new
/// set that is no longer in the staging folder but is in `dir` was moved in: it goes.
void restore_previous(const fs::path& dir, const fs::path& staging) noexcept {
  const fs::path journal = staging / journal_name;
  if (!present(journal)) return;  // publication never started: nothing was moved
  const std::vector<std::string> names = read_lines(journal);
  if (!present(staging / report_name) && present(dir / report_name)) return;  // committed
  std::error_code ec;
  for (const auto& n : names)
    if (!present(staging / n) && present(dir / n)) fs::remove_all(dir / n, ec);
  const fs::path previous = staging / previous_name;
  if (fs::is_directory(previous, ec)) {
    for (const auto& entry : fs::directory_iterator(previous, ec))
      if (entry.path().filename() != report_name) fs::rename(entry.path(), dir / entry.path().filename(), ec);
    if (present(previous / report_name)) fs::rename(previous / report_name, dir / report_name, ec);
  }
  sync_directory(dir);
}

/// Removes what dead runs left in `dir` (only called while holding the folder's lock, so every
/// staging folder there belongs to a run that is gone), putting back a set one of them had moved
/// aside.
void clean_after_dead_runs(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(staging_prefix, 0) == 0 || is_stale_temporary(name)) stale.push_back(entry.path());
  }
  for (const auto& p : stale) {
    if (fs::is_directory(fs::symlink_status(p, ec))) restore_previous(dir, p);
    fs::remove_all(p, ec);
  }
}

/// The outermost folder create_directories(dir) will create (empty when `dir` exists).
fs::path first_missing_ancestor(const fs::path& dir) {
  fs::path missing;
  for (fs::path p = fs::absolute(dir); !p.empty() && !present(p); p = p.parent_path()) {
    missing = p;
    if (p == p.parent_path()) break;
  }
  return missing;
}

}  // namespace

void OutputSet::set_step_hook_for_testing(StepHook hook) { step_hook() = std::move(hook); }

OutputSet::OutputSet(fs::path dir, bool wait, const std::function<void()>& on_wait) : m_dir(std::move(dir)) {
  if (m_dir.empty()) m_dir = ".";
  const std::string where = m_dir.string();
  for (;;) {
    const fs::path missing = first_missing_ancestor(m_dir);
    ensure_directory(m_dir);
    if (!missing.empty() && m_created_root.empty()) m_created_root = missing;
    m_lock_fd = ::open(m_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (m_lock_fd < 0)
      throw InputError(fmt::format("{}: cannot open the output folder ({})", where, std::strerror(errno)));
    if (::flock(m_lock_fd, LOCK_EX | LOCK_NB) != 0) {
      if (errno != EWOULDBLOCK) break;  // a file system without flock: go on unlocked
      if (!wait) {
        ::close(m_lock_fd);
        m_lock_fd = -1;
        throw InputError(fmt::format("{}: another cutwork run is writing into this folder (wait for it to "
                                     "finish, choose another --out, or pass --wait)",
                                     where));
      }
      if (on_wait) on_wait();
      while (::flock(m_lock_fd, LOCK_EX) != 0 && errno == EINTR) {
      }
    }
    // The run we waited for may have removed the folder (it had created it and failed): lock the
    // folder that is there now.
    struct stat locked {}, now {};
    if (::fstat(m_lock_fd, &locked) == 0 && ::stat(m_dir.c_str(), &now) == 0 && locked.st_ino == now.st_ino &&
        locked.st_dev == now.st_dev)
      break;
    ::close(m_lock_fd);
    m_lock_fd = -1;
  }
  clean_after_dead_runs(m_dir);
  m_staging = m_dir / fmt::format("{}{}", staging_prefix, ::getpid());
  std::error_code ec;
  fs::create_directory(m_staging, ec);
  if (ec) {
    release();
    throw InputError(fmt::format("{}: cannot write into the output folder ({})", where, ec.message()));
  }
}

OutputSet::~OutputSet() { release(); }

void OutputSet::release() noexcept {
  std::error_code ec;
  if (!m_staging.empty()) fs::remove_all(m_staging, ec);
  m_staging.clear();
  if (!m_published && !m_created_root.empty()) {
    // Remove the folders this run created, innermost first, as long as they are empty.
    for (fs::path p = fs::absolute(m_dir); !p.empty(); p = p.parent_path()) {
      if (!fs::remove(p, ec)) break;
      if (p == m_created_root) break;
    }
    m_created_root.clear();
  }
  if (m_lock_fd >= 0) ::close(m_lock_fd);
  m_lock_fd = -1;
}

FilePlacer placer(const fs::path& dir) {
  return [dir](const std::string& name) { return dir / name; };
}

FilePlacer placer(OutputSet& set) {
  return [&set](const std::string& name) { return set.stage(name); };
}

fs::path OutputSet::stage(const std::string& name) {
  if (name.empty() || name[0] == '.' || name.find('/') != std::string::npos)
    throw InternalError("output set: '" + name + "' is not a plain, visible file name");
  if (std::find(m_names.begin(), m_names.end(), name) == m_names.end()) m_names.push_back(name);
  return m_staging / name;
}

void OutputSet::step(const std::string& what) {
  if (step_hook()) step_hook()(m_step, what);
  ++m_step;
}

void OutputSet::roll_back() noexcept { restore_previous(m_dir, m_staging); }

void OutputSet::publish() {
  if (std::find(m_names.begin(), m_names.end(), report_name) == m_names.end())
    throw InternalError("output set: report.json was not staged (it marks a complete set)");
  for (const auto& n : m_names)
    if (!present(m_staging / n)) throw InternalError("output set: " + n + " was staged but not written");
  // The new set: its files, the manifest, report.json last.
  std::vector<std::string> incoming;
  for (const auto& n : m_names)
    if (n != report_name) incoming.push_back(n);
  incoming.push_back(manifest_name);
  std::vector<std::string> all = incoming;
  all.push_back(report_name);
  write_file_atomic(m_staging / manifest_name, join_lines(all));
  // The previous set: what its manifest names (a folder from before manifests: the new names).
  std::set<std::string> previous(incoming.begin(), incoming.end());
  for (const auto& n : read_lines(m_dir / manifest_name)) previous.insert(n);
  previous.erase(report_name);
  previous.erase(journal_name);
  previous.erase(previous_name);
  write_file_atomic(m_staging / journal_name, join_lines(all));

  const fs::path aside = m_staging / previous_name;
  m_step = 0;
  try {
    fs::create_directory(aside);
    if (present(m_dir / report_name)) {
      step("remove the previous report.json");
      fs::rename(m_dir / report_name, aside / report_name);
    }
    for (const auto& n : previous)
      if (present(m_dir / n)) {
        step("move the previous " + n + " aside");
        fs::rename(m_dir / n, aside / n);
      }
    for (const auto& n : incoming) {
      step("move " + n + " in");
      fs::rename(m_staging / n, m_dir / n);
    }
    step("move report.json in");
    fs::rename(m_staging / report_name, m_dir / report_name);
  } catch (const std::exception& e) {
    roll_back();
    std::string why = e.what();
    if (const auto* fe = dynamic_cast<const fs::filesystem_error*>(&e)) why = fe->code().message();
    throw InputError(fmt::format("{}: cannot publish the outputs ({}); the previous outputs are left in place",
                                 m_dir.string(), why));
  }
  m_published = true;
  if (m_lock_fd >= 0) ::fsync(m_lock_fd);
  std::error_code ec;
  fs::remove_all(m_staging, ec);
  m_staging.clear();
}

}  // namespace cutwork
