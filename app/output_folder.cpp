#include "app/output_folder.h"

#include "core/frame/output_file.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;

namespace ff::app {

namespace {
constexpr const char* kLockName = ".flexframe.lock";
constexpr const char* kManifestName = ".flexframe-files";
constexpr const char* kReserveName = ".flexframe-reserve";
// what a refused write says it did not do, and what the user can do
constexpr const char* kNotThrough = "; nothing was written through it (remove it, or choose another --out)";

// every byte of `text`, or false with errno set
bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// A manifest entry that stays inside the folder: relative, no "..", no empty or "." parts.
bool safe_relative(const std::string& rel) {
  if (rel.empty() || rel.front() == '/') return false;
  std::stringstream parts(rel);
  for (std::string p; std::getline(parts, p, '/');)
    if (p == ".." || p == ".") return false;
  return rel.find('\0') == std::string::npos && rel.find('\n') == std::string::npos;
}

// Walks the folders of `rel` below `dir` without following a link: each must be a real folder
// this user owns (a link, a file or another user's folder on the way would carry a write outside,
// or into someone else's files); absent ones are made when `make`. Returns why not, or "".
std::string real_folders(const fs::path& dir, const std::string& rel, bool make) {
  fs::path at = dir;
  for (const fs::path& part : fs::path(rel)) {
    if (part.empty()) continue;
    at /= part;
    struct stat st;
    if (::lstat(at.c_str(), &st) != 0) {
      if (errno == ENOENT && !make) return "";  // nothing below to check: the writer's open says why
      if (errno != ENOENT) return at.string() + ": " + write_failure_reason(errno);
      if (::mkdir(at.c_str(), 0755) != 0 || ::lstat(at.c_str(), &st) != 0)
        return "cannot create " + at.string() + ": " + write_failure_reason(errno);
    }
    if (S_ISLNK(st.st_mode)) return at.string() + " is a symbolic link that no flexframe job made";
    if (!S_ISDIR(st.st_mode)) return at.string() + " is not a folder";
    if (st.st_uid != ::geteuid()) return at.string() + " belongs to another user";
  }
  return "";
}

// The manifest's text, read without following a link or blocking on a FIFO, and bounded: a
// manifest is a few lines a file; a larger one is not flexframe's.
std::string read_manifest(const fs::path& path) {
  constexpr std::size_t kMaxManifestBytes = 64u << 20;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "";
  struct stat st;
  std::string text;
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && static_cast<std::size_t>(st.st_size) <= kMaxManifestBytes) {
    text.resize(static_cast<std::size_t>(st.st_size));
    const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
    text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  }
  ::close(fd);
  return text;
}

// No part of `rel` below `dir` is a symbolic link (so deleting it cannot reach outside).
bool reached_without_links(const fs::path& dir, const std::string& rel) {
  fs::path at = dir;
  std::error_code ec;
  for (const fs::path& part : fs::path(rel)) {
    if (part.empty()) continue;
    at /= part;
    if (fs::is_symlink(fs::symlink_status(at, ec))) return false;
  }
  return true;
}
}  // namespace

std::string write_failure_reason(int err) {
  if (err == ENOSPC || err == EDQUOT) return std::string("disk full (") + std::strerror(err) + ")";
  return std::strerror(err);
}

void write_text_file(const fs::path& path, const std::string& text) {
  // the temporary is opened as the file itself would be: a link planted at "<name>.tmp" is refused,
  // not followed (core/frame/output_file.h); rename() then replaces the name, never a link's target
  // and the name itself: rename() would replace a planted link, which is not this job's to delete
  if (const std::string why = output_entry_problem(path.string()); !why.empty())
    throw WriteError("cannot write " + path.string() + ": " + why + kNotThrough);
  const std::string tmp = path.string() + ".tmp";
  std::string why;
  const int fd = open_output_file(tmp, &why);
  if (fd < 0) throw WriteError("cannot write " + path.string() + ": " + (errno != 0 ? write_failure_reason(errno) : tmp + ": " + why + kNotThrough));
  const bool written = write_all(fd, text) && ::fsync(fd) == 0;
  const int err = errno;
  const bool closed = ::close(fd) == 0;
  const int close_err = errno;
  if (!written || !closed) {
    ::unlink(tmp.c_str());
    throw WriteError("cannot write " + path.string() + ": " + write_failure_reason(written ? close_err : err));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    ::unlink(tmp.c_str());
    throw WriteError("cannot write " + path.string() + ": " + write_failure_reason(e));
  }
}

OutputFolder::OutputFolder(const fs::path& dir, const std::string& job) : dir_(dir) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw WriteError("cannot create output folder " + dir_.string() + ": " +
                     (ec ? write_failure_reason(ec.value()) : std::string("not a folder")));
  // the lock first: nothing else in the folder is touched before it is held
  const fs::path lock_path = dir_ / kLockName;
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
  if (lock_fd_ < 0)
    throw WriteError("cannot write " + lock_path.string() + ": " +
                     (errno == ELOOP ? std::string("it is a symbolic link that no flexframe job made") : write_failure_reason(errno)));
  if (struct stat st; ::fstat(lock_fd_, &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink > 1) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw WriteError("cannot write " + lock_path.string() + ": it is not a regular file of its own (a link or a device)");
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    char holder[128] = {0};
    const ssize_t n = ::pread(lock_fd_, holder, sizeof holder - 1, 0);
    std::string who = n > 0 ? std::string(holder, static_cast<std::size_t>(n)) : std::string("another process");
    while (!who.empty() && (who.back() == '\n' || who.back() == ' ')) who.pop_back();
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw std::runtime_error("output folder " + dir_.string() + " is in use by " + who +
                             "; nothing in it was changed (wait for that job, or choose another --out)");
  }
  const std::string me = "flexframe " + job + " (pid " + std::to_string(::getpid()) + ")\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size())) {
    const int e = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw WriteError("cannot write " + lock_path.string() + ": " + write_failure_reason(e));
  }
  // the reserve for the final records (posix_fallocate: real blocks, not a sparse file)
  {
    const fs::path reserve = dir_ / kReserveName;
    std::string why;
    const int fd = open_output_file(reserve.string(), &why);
    if (fd < 0 && errno == 0) {
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw WriteError("cannot write " + reserve.string() + ": " + why);
    }
    int e = fd < 0 ? errno : ::posix_fallocate(fd, 0, static_cast<off_t>(kReserveBytes));
    if (fd >= 0 && e == EOPNOTSUPP) {  // a file system without fallocate: write the bytes
      const std::string zeros(kReserveBytes, '\0');
      e = write_all(fd, zeros) && ::fsync(fd) == 0 ? 0 : errno;
    }
    if (fd >= 0 && ::close(fd) != 0 && e == 0) e = errno;
    if (e != 0) {
      ::unlink(reserve.c_str());
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw WriteError("cannot write in " + dir_.string() + ": " + write_failure_reason(e) + "; a job needs at least " +
                       std::to_string(kReserveBytes / 1024) + " KiB free to start");
    }
    reserve_held_ = true;
  }
  // what earlier jobs wrote here, as far as it still exists
  std::istringstream in(read_manifest(dir_ / kManifestName));
  for (std::string line; std::getline(in, line);) {
    if (!safe_relative(line)) continue;
    const bool folder = line.back() == '/';
    const fs::path p = dir_ / (folder ? line.substr(0, line.size() - 1) : line);
    if (fs::exists(fs::symlink_status(p, ec))) recorded_.insert(line);
  }
  rewrite_manifest();
}

OutputFolder::~OutputFolder() {
  release_reserve();
  if (manifest_fd_ >= 0) ::close(manifest_fd_);
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

void OutputFolder::rewrite_manifest() {
  std::string text;
  for (const std::string& r : recorded_) text += r + "\n";
  write_text_file(dir_ / kManifestName, text);
  if (manifest_fd_ >= 0) ::close(manifest_fd_);
  manifest_fd_ = ::open((dir_ / kManifestName).c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOFOLLOW);
  if (manifest_fd_ < 0) throw WriteError("cannot write " + (dir_ / kManifestName).string() + ": " + write_failure_reason(errno));
}

void OutputFolder::release_reserve() {
  std::lock_guard lock(mutex_);
  if (!reserve_held_) return;
  ::unlink((dir_ / kReserveName).c_str());
  reserve_held_ = false;
}

void OutputFolder::record(const std::string& relative) {
  if (!safe_relative(relative)) throw std::logic_error("OutputFolder::record: not a path inside the folder: " + relative);
  std::lock_guard lock(mutex_);
  if (!recorded_.insert(relative).second) return;
  if (!write_all(manifest_fd_, relative + "\n")) {
    const int e = errno;
    recorded_.erase(relative);
    throw WriteError("cannot write " + (dir_ / kManifestName).string() + ": " + write_failure_reason(e));
  }
}

fs::path OutputFolder::file(const std::string& relative) {
  record(relative);
  const fs::path p = dir_ / relative;
  std::string why = real_folders(dir_, fs::path(relative).parent_path().string(), false);
  if (why.empty()) why = output_entry_problem(p.string());
  if (!why.empty()) throw WriteError("cannot write " + p.string() + ": " + why + kNotThrough);
  return p;
}

fs::path OutputFolder::sub_folder(const std::string& relative) {
  record(relative + "/");
  const fs::path p = dir_ / relative;
  if (const std::string why = real_folders(dir_, relative, true); !why.empty())
    throw WriteError("cannot create " + p.string() + ": " + why + kNotThrough);
  return p;
}

std::size_t OutputFolder::remove_earlier(const std::string& prefix) {
  std::lock_guard lock(mutex_);
  std::size_t removed = 0;
  std::vector<std::string> folders;
  std::error_code ec;
  for (auto it = recorded_.begin(); it != recorded_.end();) {
    const std::string& rel = *it;
    if (rel.rfind(prefix, 0) != 0) {
      ++it;
      continue;
    }
    if (rel.back() == '/') {
      folders.push_back(rel);
      ++it;
      continue;
    }
    const fs::path p = dir_ / rel;
    if (reached_without_links(dir_, fs::path(rel).parent_path().string())) {
      const fs::file_status st = fs::symlink_status(p, ec);
      if (fs::is_regular_file(st) || fs::is_symlink(st)) {  // a link itself, never its target
        if (fs::remove(p, ec)) ++removed;
      }
    }
    it = recorded_.erase(it);
  }
  // deepest first, and only when empty: a folder that holds anything else stays
  std::sort(folders.rbegin(), folders.rend());
  for (const std::string& rel : folders) {
    const fs::path p = dir_ / rel.substr(0, rel.size() - 1);
    if (reached_without_links(dir_, rel.substr(0, rel.size() - 1)) && fs::is_directory(fs::symlink_status(p, ec)) &&
        fs::is_empty(p, ec))
      fs::remove(p, ec);
    if (!fs::exists(fs::symlink_status(p, ec))) recorded_.erase(rel);
  }
  rewrite_manifest();
  return removed;
}

std::size_t OutputFolder::unrecorded_files(const std::string& relative, const std::string& ext) const {
  std::size_t n = 0;
  std::error_code ec;
  const fs::path sub = dir_ / relative;
  if (!reached_without_links(dir_, relative) || !fs::is_directory(sub, ec)) return 0;
  for (const auto& e : fs::directory_iterator(sub, ec)) {
    if (e.path().extension() != ext || !e.is_regular_file(ec)) continue;
    if (!recorded_.count((fs::path(relative) / e.path().filename()).string())) ++n;
  }
  return n;
}

}  // namespace ff::app
