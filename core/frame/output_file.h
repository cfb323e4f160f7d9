#pragma once
/// \file output_file.h
/// Opening an output file without being redirected. Every file FlexFrame writes itself (PNGs,
/// VTU and PVD files, summaries, CSV tables, mesh exports, temporaries) is opened here, so that a
/// symbolic link, a hard link, a FIFO or a device planted where an output goes cannot turn the
/// write into one outside the output folder (docs/guide/running.md, "What a run may touch").
/// The folders on the way are the OutputFolder's to check (app/output_folder.h); this guards the
/// last component, which a writer opens itself.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace ff {

/// Why the existing entry at `path` may not be written over, or "" when it may (absent, or a
/// regular file with no other name). Does not follow a link at the last component.
inline std::string output_entry_problem(const std::string& path) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) return errno == ENOENT ? "" : std::strerror(errno);
  if (S_ISLNK(st.st_mode)) return "it is a symbolic link that no flexframe job made";
  if (!S_ISREG(st.st_mode)) return "it is not a regular file";
  if (st.st_nlink > 1) return "it is a hard link to a file that has other names";
  return "";
}

/// Opens `path` for writing as an empty regular file of its own: created when absent (mode 0644),
/// truncated when it is a regular file with one name. Refuses a symbolic link (O_NOFOLLOW), a
/// hard link to another name, a FIFO or device (opened non-blocking, then checked), so nothing is
/// truncated or written that is not this file. Returns the descriptor (close-on-exec), or -1 with
/// `why` saying what was refused or the system's reason; errno is then the system's error, or 0
/// for a refusal (so that a caller can word ENOSPC as a full disk).
inline int open_output_file(const std::string& path, std::string* why) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int e = errno;
    if (why) *why = e == ELOOP ? "it is a symbolic link that no flexframe job made" : std::strerror(e);
    errno = e == ELOOP ? 0 : e;
    return -1;
  }
  struct stat st;
  std::string problem;
  int err = 0;
  if (::fstat(fd, &st) != 0) err = errno;
  else if (!S_ISREG(st.st_mode)) problem = "it is not a regular file";
  else if (st.st_nlink > 1) problem = "it is a hard link to a file that has other names";
  else if (::ftruncate(fd, 0) != 0 || ::fcntl(fd, F_SETFL, 0) != 0) err = errno;  // F_SETFL: blocking again
  if (err != 0 || !problem.empty()) {
    ::close(fd);
    if (why) *why = err != 0 ? std::strerror(err) : problem;
    errno = err;
    return -1;
  }
  return fd;
}

/// open_output_file as a stdio stream ("wb"), or nullptr with `why`.
inline std::FILE* open_output_stream(const std::string& path, std::string* why) {
  const int fd = open_output_file(path, why);
  if (fd < 0) return nullptr;
  std::FILE* f = ::fdopen(fd, "wb");
  if (!f) {
    const int e = errno;
    if (why) *why = std::strerror(e);
    ::close(fd);
    errno = e;
  }
  return f;
}

}  // namespace ff
