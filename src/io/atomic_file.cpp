#include "cgamesh/io/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <set>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace cgamesh::io {
namespace {

namespace fs = std::filesystem;

std::string system_error_text(int error) { return std::strerror(error); }

[[noreturn]] void fail(const std::string& what, const fs::path& path, int error) {
  throw WriteError(what + " '" + path.string() + "': " + system_error_text(error));
}

fs::path directory_of(const fs::path& path) {
  const fs::path dir = path.parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

/// A fresh name `.NAME.KIND-XXXXXXXX` next to `target` (not created).
fs::path sibling_name(const fs::path& target, const char* kind) {
  thread_local std::mt19937_64 rng{std::random_device{}()};
  std::string base = target.filename().string();
  if (base.size() > 200) base.resize(200);  // stay below NAME_MAX with the suffix
  char suffix[17];
  std::snprintf(suffix, sizeof suffix, "%08llx", static_cast<unsigned long long>(rng() & 0xffffffffULL));
  return directory_of(target) / ("." + base + "." + kind + "-" + suffix);
}

/// Closes a descriptor on scope exit unless released.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  [[nodiscard]] int get() const noexcept { return fd_; }
  /// Closes now; returns the errno of a failed close, or 0.
  int close() {
    const int fd = fd_;
    fd_ = -1;
    return ::close(fd) == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

/// Creates a new temporary file next to `target` holding `bytes`, flushed to disk.
fs::path write_temporary(const fs::path& target, std::string_view bytes) {
  fs::path temp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp = sibling_name(target, "tmp");
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) fail("cannot create a temporary file for", target, errno);
  }
  if (fd < 0) fail("cannot create a temporary file for", target, EEXIST);
  Fd file(fd);
  try {
    const char* data = bytes.data();
    std::size_t left = bytes.size();
    while (left > 0) {
      const ssize_t n = ::write(file.get(), data, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        fail("cannot write", target, errno);
      }
      data += n;
      left -= static_cast<std::size_t>(n);
    }
    if (::fsync(file.get()) != 0 && errno != EINVAL) fail("cannot flush", target, errno);
    if (const int error = file.close(); error != 0) fail("cannot close", target, error);
  } catch (...) {
    ::unlink(temp.c_str());
    throw;
  }
  return temp;
}

/// Flushes a directory entry change to disk (best effort: not every file system allows it).
void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

struct Pending {
  fs::path target;
  fs::path temp;    ///< empty once renamed
  fs::path backup;  ///< hard link to the previous target, or empty
  bool existed = false;
  bool renamed = false;
};

/// Undoes everything: removes temporaries, restores replaced targets, removes backups.
void roll_back(std::vector<Pending>& pending) noexcept {
  for (Pending& p : pending) {
    if (!p.renamed) {
      if (!p.temp.empty()) ::unlink(p.temp.c_str());
    } else if (!p.backup.empty()) {
      if (::rename(p.backup.c_str(), p.target.c_str()) == 0) p.backup.clear();
    } else if (!p.existed) {
      ::unlink(p.target.c_str());
    }
    if (!p.backup.empty()) ::unlink(p.backup.c_str());
  }
}

}  // namespace

void write_files_atomically(std::span<const OutputFile> files) {
  std::set<fs::path> seen;
  for (const OutputFile& f : files) {
    if (f.path.empty() || !f.path.has_filename())
      throw InvalidInputError("output path '" + f.path.string() + "' names no file");
    if (!seen.insert(fs::absolute(f.path).lexically_normal()).second)
      throw InvalidInputError("output path '" + f.path.string() + "' appears twice");
  }

  std::vector<Pending> pending;
  pending.reserve(files.size());
  try {
    for (const OutputFile& f : files) {
      Pending p;
      p.target = f.path;
      p.temp = write_temporary(f.path, f.bytes);
      pending.push_back(std::move(p));
    }
    // Keep the previous targets reachable so a failed rename further down can restore them.
    for (Pending& p : pending) {
      struct stat st {};
      p.existed = ::lstat(p.target.c_str(), &st) == 0;
      if (!p.existed || S_ISDIR(st.st_mode)) continue;
      for (int attempt = 0; attempt < 100; ++attempt) {
        fs::path backup = sibling_name(p.target, "bak");
        if (::link(p.target.c_str(), backup.c_str()) == 0) {
          p.backup = std::move(backup);
          break;
        }
        if (errno != EEXIST) break;  // no hard links here: the old file cannot be restored
      }
    }
    for (Pending& p : pending) {
      if (::rename(p.temp.c_str(), p.target.c_str()) != 0) fail("cannot replace", p.target, errno);
      p.renamed = true;
    }
  } catch (...) {
    roll_back(pending);
    throw;
  }
  std::set<fs::path> dirs;
  for (Pending& p : pending) {
    if (!p.backup.empty()) ::unlink(p.backup.c_str());
    dirs.insert(directory_of(p.target));
  }
  for (const fs::path& dir : dirs) sync_directory(dir);
}

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
  const OutputFile file{path, bytes};
  write_files_atomically(std::span<const OutputFile>(&file, 1));
}

void write_files_atomically(std::span<const EncodedFile> files) {
  std::vector<OutputFile> views;
  views.reserve(files.size());
  for (const EncodedFile& f : files) views.push_back({f.path, f.bytes});
  write_files_atomically(std::span<const OutputFile>(views));
}

}  // namespace cgamesh::io
