#include "host/core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <system_error>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {
namespace fs = std::filesystem;

namespace {
fs::path temporary_beside(const fs::path& path) {
  std::random_device rd;
  return path.parent_path() / fmt::format(".{}.tmp{}", path.filename().string(), rd() % 1000000u);
}

/// Flushes the file's data to the disk, so that the rename cannot outlive the content after a
/// crash of the machine (best effort: a file system without fsync just skips it).
void sync_to_disk(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}
}  // namespace

void ensure_directory(const fs::path& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError(dir.string() + ": cannot create output directory" +
                     (ec ? " (" + ec.message() + ")" : std::string(" (a file of that name exists)")));
}

void write_file_atomic(const fs::path& path, const std::function<void(std::ostream&)>& write,
                       bool binary) {
  const fs::path tmp = temporary_beside(path);
  {
    std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
    if (!out) throw InputError(path.string() + ": cannot open for writing");
    try {
      write(out);
    } catch (...) {
      out.close();
      std::error_code ignore;
      fs::remove(tmp, ignore);
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::error_code ignore;
      fs::remove(tmp, ignore);
      throw InputError(path.string() + ": write failed (disk full?)");
    }
  }
  sync_to_disk(tmp);
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignore;
    fs::remove(tmp, ignore);
    throw InputError(path.string() + ": cannot move the finished file into place (" + ec.message() +
                     ")");
  }
}

void write_file_atomic(const fs::path& path, std::string_view content) {
  write_file_atomic(path, [&](std::ostream& out) { out.write(content.data(), std::streamsize(content.size())); },
                    true);
}

}  // namespace cutwork
