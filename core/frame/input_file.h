#pragma once
/// \file input_file.h
/// The one way a file named by a scene or by the user is opened for reading: scene and study
/// files, reference tables, action files, mesh and CAD files of every format, results files.
/// - Only a regular file is read. A path may be a link (a user's own link to a mesh file is
///   ordinary input), but what it resolves to must be a regular file: a FIFO blocks open() until
///   someone writes to it (SIGTERM cannot end that), and /dev/zero or /dev/urandom never end.
///   The type is checked with stat() before the file is opened (a device is never opened) and
///   again on the open descriptor (a file swapped in between is caught); the open does not block.
/// - Its size is checked against a bound before anything is read, and a reader that reads the
///   whole file reads no more than that bound (a file that grows while read is refused).
/// Libraries that open files by name (assimp, Gmsh, HDF5) get the name only after this check.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace ff {

/// Text files are read whole (scenes, studies, reference tables, action files): at most this
/// many bytes. The largest bundled one is a few kB; 100 MB of TOML or CSV is already far more
/// than any scene or reference curve needs.
inline constexpr std::uintmax_t kMaxTextInputBytes = 100'000'000;
/// What kMaxTextInputBytes bounds, for messages ("is 2 GB, more than the 100 MB ...")
inline constexpr const char* kTextInputBound = "a scene, study, reference or action file may be";

/// "2.5 GB", "310 MB", "512 bytes"
inline std::string input_bytes_words(double bytes) {
  char b[48];
  if (bytes >= 1e9) std::snprintf(b, sizeof b, "%.3g GB", bytes / 1e9);
  else if (bytes >= 1e6) std::snprintf(b, sizeof b, "%.3g MB", bytes / 1e6);
  else std::snprintf(b, sizeof b, "%.0f bytes", bytes);
  return b;
}

namespace input_file_detail {

inline std::string kind_words(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// "is a named pipe (FIFO), not a regular file", or, for a link, what it leads to
inline std::string not_regular(const std::string& path, mode_t mode) {
  std::string is = "is ";
  struct stat own {};
  if (::lstat(path.c_str(), &own) == 0 && S_ISLNK(own.st_mode)) {
    char* target = ::realpath(path.c_str(), nullptr);
    is = "is a link to '" + std::string(target ? target : "?") + "', which is ";
    std::free(target);
  }
  return is + kind_words(mode) + ", not a regular file; FlexFrame reads only regular files (a pipe or a device "
         "would block the read or never end)";
}

inline std::string too_large(double size, std::uintmax_t max_bytes, const std::string& bound_words) {
  return "is " + input_bytes_words(size) + ", more than the " + input_bytes_words(static_cast<double>(max_bytes)) +
         " " + bound_words;
}

}  // namespace input_file_detail

/// Opens `path` for reading when it is (or its link leads to) a regular file of at most
/// `max_bytes` (0: no size bound; for files a library reads in parts, such as results.h5):
/// returns the descriptor (O_RDONLY, close-on-exec; the caller closes it) and its size in *size.
/// Otherwise returns -1 and sets *problem to what completes "<the file> ...", e.g. "is a named
/// pipe (FIFO), not a regular file; ..." or "is 12 GB, more than the 8 GB of memory ...".
inline int open_input_file(const std::string& path, std::uintmax_t max_bytes, const std::string& bound_words,
                           std::string* problem, std::uintmax_t* size = nullptr) {
  using namespace input_file_detail;
  const auto refuse = [&](const std::string& why) {
    if (problem) *problem = why;
    return -1;
  };
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return refuse(errno == ENOENT ? std::string("does not exist")
                                  : errno == ELOOP ? std::string("is a link that leads in a circle")
                                                   : "cannot be read: " + std::string(std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) return refuse(not_regular(path, st.st_mode));
  if (max_bytes > 0 && static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    return refuse(too_large(static_cast<double>(st.st_size), max_bytes, bound_words));
  // O_NONBLOCK: should a FIFO have been swapped in after stat(), open() returns instead of waiting
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return refuse("cannot be opened: " + std::string(std::strerror(errno)));
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) ||
      (max_bytes > 0 && static_cast<std::uintmax_t>(st.st_size) > max_bytes)) {
    ::close(fd);
    return refuse("changed while it was being opened (it is no longer a regular file of the size seen a moment "
                  "before)");
  }
  if (size) *size = static_cast<std::uintmax_t>(st.st_size);
  return fd;
}

/// open_input_file's checks alone, for a file a library then opens by its name: "" when `path`
/// may be read, else what completes "<the file> ...".
inline std::string input_file_problem(const std::string& path, std::uintmax_t max_bytes,
                                      const std::string& bound_words) {
  std::string problem;
  const int fd = open_input_file(path, max_bytes, bound_words, &problem);
  if (fd >= 0) ::close(fd);
  return problem;
}

/// The whole of `path` into *text, after open_input_file's checks, reading at most `max_bytes`
/// (> 0). False with *problem set as there (a file that grew past the bound while being read is
/// refused the same way).
inline bool read_input_file(const std::string& path, std::string* text, std::uintmax_t max_bytes,
                            const std::string& bound_words, std::string* problem) {
  std::uintmax_t size = 0;
  const int fd = open_input_file(path, max_bytes, bound_words, problem, &size);
  if (fd < 0) return false;
  std::string out;
  out.reserve(static_cast<std::size_t>(size));
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      if (problem) *problem = "cannot be read: " + std::string(std::strerror(errno));
      ::close(fd);
      return false;
    }
    if (n == 0) break;
    if (out.size() + static_cast<std::size_t>(n) > max_bytes) {
      if (problem) *problem = input_file_detail::too_large(static_cast<double>(out.size() + n), max_bytes, bound_words);
      ::close(fd);
      return false;
    }
    out.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  if (text) *text = std::move(out);
  return true;
}

/// The whole text file at `path` (a scene, a study, a summary), or "" when it cannot be read:
/// for callers that say why elsewhere (a validator that opens it again, a missing result).
inline std::string read_text_or_empty(const std::string& path) {
  std::string text;
  read_input_file(path, &text, kMaxTextInputBytes, kTextInputBound, nullptr);
  return text;
}

}  // namespace ff
