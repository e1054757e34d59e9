#pragma once
/// Output sets, all or nothing: every file a run writes is staged in a private folder inside the
/// output folder and published together, so that the output folder holds either the complete
/// previous set or the complete new one — never a new stencils.json beside an old report.json.
///
/// A set is complete when its `report.json` is present: publishing removes the old report.json
/// first, moves the previous set's files aside, moves the new files in (with the manifest
/// `.cutwork-outputs`, the names of the set) and `report.json` last, then flushes the folder to
/// the disk. A failure at any step before the last rename puts the previous set back; a run
/// killed part way leaves its staging folder, which the next run into the folder uses to put the
/// previous set back before it starts (stale temporaries of dead runs are removed then too).
///
/// The folder is locked (flock on the folder itself, advisory) for the whole life of the
/// OutputSet: a second run into the same folder fails at once with a message saying so, or waits.
/// A run that fails before publishing removes what it staged, and the folder itself when it
/// created it and it is empty: a failed run into a new folder writes nothing.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace cutwork {

/// Where the output file `name` of a set is to be written: straight into a folder (placer(dir)) or
/// into an OutputSet's staging (placer(set)), so that one writer serves both.
using FilePlacer = std::function<std::filesystem::path(const std::string& name)>;

class OutputSet;
FilePlacer placer(const std::filesystem::path& dir);
FilePlacer placer(OutputSet& set);

class OutputSet {
 public:
  /// Creates `dir` if needed, locks it, puts back the previous set of a run that died while
  /// publishing, removes stale staging folders and temporaries, and makes this run's staging
  /// folder. Throws InputError naming `dir` when it cannot be created or written, or when another
  /// run holds the lock and `wait` is false. With `wait`, blocks until the other run has finished
  /// (`on_wait` is called once first, e.g. to say so).
  explicit OutputSet(std::filesystem::path dir, bool wait = false,
                     const std::function<void()>& on_wait = {});
  /// Unpublished: removes the staging folder (and `dir` when this run created it and it is empty).
  /// Releases the lock.
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  const std::filesystem::path& dir() const { return m_dir; }
  /// Where to write the output `name` (a plain file name such as "report.json"); the file must
  /// exist there when publish() is called. Names are published in the order staged, report.json
  /// last whatever its order.
  std::filesystem::path stage(const std::string& name);
  /// Publishes the staged files as the folder's new set (see the file comment). Throws
  /// InputError naming the folder when a step fails; the previous set is then in place again.
  /// Throws InternalError when report.json or a staged file was not written (a bug: nothing moves).
  void publish();

  /// The manifest's file name.
  static constexpr const char* manifest_name = ".cutwork-outputs";

  /// Test hook: called before every publishing step with its number (0, 1, ...) and a word on
  /// what it does; it may throw (a failed step) or end the process (a kill). Empty: none.
  using StepHook = std::function<void(int step, const std::string& what)>;
  static void set_step_hook_for_testing(StepHook hook);

 private:
  void step(const std::string& what);
  void roll_back() noexcept;
  void release() noexcept;

  std::filesystem::path m_dir, m_staging;
  std::vector<std::string> m_names;
  int m_lock_fd = -1;
  int m_step = 0;
  std::filesystem::path m_created_root;  ///< the outermost folder this run created (empty: none)
  bool m_published = false;
};

}  // namespace cutwork
