#pragma once
// Shared by the cli tests: running the flexframe executable as a child process (fork/exec,
// stdout and stderr captured to files, exit status), one output folder per test, a small JSON
// reader for summary.json and PNG read-back through VTK.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "tests/render/render_test_support.h"

namespace ff::cli::test {

namespace fs = std::filesystem;

/// How much slower than a release build the executable under test runs: FF_TEST_SLOWDOWN, which
/// scripts/sanitize sets (ThreadSanitizer 10, AddressSanitizer 4), else 1. Every deadline a test
/// gives a child is scaled by it, so an instrumented run is judged by what it does, not by a clock
/// sized for optimized code.
inline double slowdown() {
  const char* s = std::getenv("FF_TEST_SLOWDOWN");
  const double f = s ? std::strtod(s, nullptr) : 1.0;
  return f >= 1.0 && f <= 100.0 ? f : 1.0;
}

inline std::string flexframe_exe() { return std::string(FF_BINARY_DIR) + "/flexframe"; }
inline std::string scene_dir() { return std::string(FF_SOURCE_DIR) + "/assets/scenes"; }
inline std::string scene_path(const std::string& name) { return scene_dir() + "/" + name + ".toml"; }

/// Names (file stems) of the bundled scenes, sorted.
inline std::vector<std::string> bundled_scene_names() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(scene_dir(), ec))
    if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// FF_BINARY_DIR/test_out/cli/<suite>.<test> (parameterized names with '/' -> '_'), emptied.
inline std::string fresh_test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(info->test_suite_name()) + "." + info->name();
  std::replace(name.begin(), name.end(), '/', '_');
  const fs::path dir = fs::path(FF_BINARY_DIR) / "test_out" / "cli" / name;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  return dir.string();
}

// ---- child processes ------------------------------------------------------------------------

struct ProcResult {
  int exit_code = -1;    ///< WEXITSTATUS when the child exited normally, else -1
  int signal = 0;        ///< terminating signal when the child was killed, else 0
  bool timed_out = false;
  double wall_s = 0.0;
  std::string out, err;  ///< captured stdout and stderr
  std::string describe() const {
    std::ostringstream s;
    s << "exit " << exit_code;
    if (signal) s << ", killed by signal " << signal;
    if (timed_out) s << ", TIMED OUT";
    s << " after " << wall_s << " s\n--- stdout ---\n" << out << "--- stderr ---\n" << err;
    return s.str();
  }
};

/// A started child; its stdout/stderr go to log files (no pipe can fill up and block it).
class Child {
 public:
  /// Starts FF_BINARY_DIR/flexframe with `args`; logs to <log_prefix>.stdout.txt/.stderr.txt;
  /// the child runs in `cwd` when given. A non-empty `launcher` (e.g. {mpirun, -n, 2}) is
  /// executed instead, with flexframe and `args` after it.
  /// `exe` replaces FF_BINARY_DIR/flexframe (e.g. the MPI build's).
  Child(const std::vector<std::string>& args, const std::string& log_prefix, const std::string& cwd = "",
        const std::vector<std::string>& launcher = {}, const std::string& exe = flexframe_exe())
      : out_file_(log_prefix + ".stdout.txt"), err_file_(log_prefix + ".stderr.txt") {
    std::vector<std::string> all = launcher;
    all.push_back(exe);
    all.insert(all.end(), args.begin(), args.end());
    const std::string program = all.front();
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    start_ = std::chrono::steady_clock::now();
    pid_ = fork();
    if (pid_ == 0) {  // child: only async-signal-safe calls until exec
      const int o = open(out_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = open(err_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (o < 0 || e < 0) _exit(126);
      dup2(o, STDOUT_FILENO);
      dup2(e, STDERR_FILENO);
      close(o);
      close(e);
      if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(125);
      signal(SIGINT, SIG_DFL);
      execv(program.c_str(), argv.data());
      _exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0 && !reaped_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  /// True while the child has not exited (reaps it when it has; wait() then reports it).
  bool running() {
    if (reaped_) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      reaped_ = true;
      status_ = status;
      end_ = std::chrono::steady_clock::now();
      return false;
    }
    return true;
  }
  bool send(int sig) { return !reaped_ && kill(pid_, sig) == 0; }

  /// Waits up to timeout_s (then SIGKILL) and returns the exit status and captured output.
  ProcResult wait(double timeout_s) {
    ProcResult r;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s * slowdown());
    while (running()) {
      if (std::chrono::steady_clock::now() > deadline) {
        r.timed_out = true;
        kill(pid_, SIGKILL);
        int status = 0;
        waitpid(pid_, &status, 0);
        reaped_ = true;
        status_ = status;
        end_ = std::chrono::steady_clock::now();
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (WIFEXITED(status_)) r.exit_code = WEXITSTATUS(status_);
    if (WIFSIGNALED(status_)) r.signal = WTERMSIG(status_);
    r.wall_s = std::chrono::duration<double>(end_ - start_).count();
    r.out = read_text(out_file_);
    r.err = read_text(err_file_);
    return r;
  }

 private:
  std::string out_file_, err_file_;
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
  std::chrono::steady_clock::time_point start_, end_;
};

/// Runs flexframe to completion (60 s limit).
inline ProcResult run_flexframe(const std::vector<std::string>& args, const std::string& log_prefix,
                                const std::string& cwd = "", double timeout_s = 60.0) {
  Child c(args, log_prefix, cwd);
  if (!c.started()) {
    ProcResult r;
    r.err = std::string("fork failed: ") + std::strerror(errno);
    return r;
  }
  return c.wait(timeout_s);
}

/// The children of process `pid` (every thread's, from /proc/<pid>/task/<tid>/children).
inline std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& t : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream in(t.path() / "children");
    for (pid_t c; in >> c;) out.push_back(c);
  }
  return out;
}

/// True when process `pid` has ended: gone, or a zombie its (new) parent has not reaped yet.
inline bool process_ended(pid_t pid) {
  const std::string stat = read_text("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t name_end = stat.rfind(')');  // the command name may hold spaces
  return name_end == std::string::npos || stat.compare(name_end + 1, 3, " Z ") == 0 || stat.compare(name_end + 1, 3, " X ") == 0;
}

/// Files and folders below `dir` (relative paths), sorted.
inline std::vector<std::string> tree(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator(); ++it)
    out.push_back(fs::relative(it->path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

/// The PNG files directly in `dir` (full paths), sorted.
inline std::vector<std::string> pngs_in(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".png") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

// ---- a small JSON reader (enough for summary.json) ---------------------------------------------

struct Json {
  enum class Kind { null, boolean, number, string, array, object };
  Kind kind = Kind::null;
  bool boolean = false;
  double number = 0.0;
  std::string string;
  std::vector<Json> array;
  std::vector<std::pair<std::string, Json>> object;

  /// Member `key` of an object, nullptr if absent or not an object.
  const Json* get(const std::string& key) const {
    if (kind != Kind::object) return nullptr;
    for (const auto& [k, v] : object)
      if (k == key) return &v;
    return nullptr;
  }
  bool is_number() const { return kind == Kind::number; }
  bool is_string() const { return kind == Kind::string; }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : s_(text) {}

  std::optional<Json> parse(std::string* error) {
    Json v;
    if (!value(v, 0) || (skip(), pos_ != s_.size())) {
      if (error_.empty()) error_ = "trailing characters";
      if (error) *error = error_ + " at offset " + std::to_string(pos_);
      return std::nullopt;
    }
    return v;
  }

 private:
  void skip() {
    while (pos_ < s_.size() && std::strchr(" \t\r\n", s_[pos_]) != nullptr) ++pos_;
  }
  bool fail(const std::string& m) {
    if (error_.empty()) error_ = m;
    return false;
  }
  bool literal(const char* word) {
    const std::size_t n = std::strlen(word);
    if (s_.compare(pos_, n, word) != 0) return fail(std::string("expected ") + word);
    pos_ += n;
    return true;
  }
  bool str(std::string& out) {
    if (s_[pos_] != '"') return fail("expected a string");
    ++pos_;
    while (pos_ < s_.size() && s_[pos_] != '"') {
      char c = s_[pos_++];
      if (static_cast<unsigned char>(c) < 0x20) return fail("control character in a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (pos_ >= s_.size()) return fail("unterminated escape");
      c = s_[pos_++];
      switch (c) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          if (pos_ + 4 > s_.size()) return fail("short \\u escape");
          const unsigned cp = static_cast<unsigned>(std::stoul(s_.substr(pos_, 4), nullptr, 16));
          pos_ += 4;
          if (cp < 0x80) {
            out += static_cast<char>(cp);
          } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
          } else {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
          }
          break;
        }
        default: return fail("bad escape");
      }
    }
    if (pos_ >= s_.size()) return fail("unterminated string");
    ++pos_;
    return true;
  }
  bool value(Json& v, int depth) {
    if (depth > 64) return fail("nested too deeply");
    skip();
    if (pos_ >= s_.size()) return fail("unexpected end");
    const char c = s_[pos_];
    if (c == '{') {
      v.kind = Json::Kind::object;
      ++pos_;
      skip();
      if (pos_ < s_.size() && s_[pos_] == '}') return ++pos_, true;
      while (true) {
        skip();
        std::string key;
        if (pos_ >= s_.size() || !str(key)) return fail("expected a key");
        skip();
        if (pos_ >= s_.size() || s_[pos_] != ':') return fail("expected ':'");
        ++pos_;
        Json member;
        if (!value(member, depth + 1)) return false;
        v.object.emplace_back(std::move(key), std::move(member));
        skip();
        if (pos_ < s_.size() && s_[pos_] == ',') { ++pos_; continue; }
        if (pos_ < s_.size() && s_[pos_] == '}') return ++pos_, true;
        return fail("expected ',' or '}'");
      }
    }
    if (c == '[') {
      v.kind = Json::Kind::array;
      ++pos_;
      skip();
      if (pos_ < s_.size() && s_[pos_] == ']') return ++pos_, true;
      while (true) {
        Json element;
        if (!value(element, depth + 1)) return false;
        v.array.push_back(std::move(element));
        skip();
        if (pos_ < s_.size() && s_[pos_] == ',') { ++pos_; continue; }
        if (pos_ < s_.size() && s_[pos_] == ']') return ++pos_, true;
        return fail("expected ',' or ']'");
      }
    }
    if (c == '"') return v.kind = Json::Kind::string, str(v.string);
    if (c == 't') return v.kind = Json::Kind::boolean, v.boolean = true, literal("true");
    if (c == 'f') return v.kind = Json::Kind::boolean, v.boolean = false, literal("false");
    if (c == 'n') return v.kind = Json::Kind::null, literal("null");
    // number: strict JSON grammar, value by strtod
    const std::size_t start = pos_;
    if (s_[pos_] == '-') ++pos_;
    const auto digits = [&] {
      const std::size_t d = pos_;
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      return pos_ > d;
    };
    if (!digits()) return fail("expected a value");
    if (pos_ < s_.size() && s_[pos_] == '.' && (++pos_, !digits())) return fail("bad number");
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
      if (!digits()) return fail("bad exponent");
    }
    v.kind = Json::Kind::number;
    v.number = std::strtod(s_.substr(start, pos_ - start).c_str(), nullptr);
    return true;
  }

  const std::string& s_;
  std::size_t pos_ = 0;
  std::string error_;
};

inline std::optional<Json> parse_json(const std::string& text, std::string* error) {
  return JsonParser(text).parse(error);
}

/// Parses DIR/summary.json; nullopt (with *error) if missing or not JSON.
inline std::optional<Json> read_summary(const std::string& out_dir, std::string* error) {
  const std::string path = out_dir + "/summary.json";
  if (!fs::is_regular_file(path)) {
    *error = path + " does not exist";
    return std::nullopt;
  }
  return parse_json(read_text(path), error);
}

/// Checks the keys every summary.json has, with their JSON types (gtest failures, no abort).
inline void expect_summary_shape(const Json& s) {
  ASSERT_EQ(s.kind, Json::Kind::object);
  for (const char* k : {"scene", "status", "reason", "time_unit"}) {
    const Json* v = s.get(k);
    EXPECT_TRUE(v && v->is_string()) << "summary.json: \"" << k << "\" missing or not a string";
  }
  for (const char* k : {"stop_time", "wall_time_s", "steps", "newton_iterations", "jacobian_updates"}) {
    const Json* v = s.get(k);
    EXPECT_TRUE(v && v->is_number() && std::isfinite(v->number) && v->number >= 0)
        << "summary.json: \"" << k << "\" missing or not a non-negative number";
  }
  const Json* effects = s.get("effects");
  ASSERT_TRUE(effects && effects->kind == Json::Kind::array) << "summary.json: \"effects\" is not a list";
  EXPECT_FALSE(effects->array.empty());
  for (const Json& e : effects->array) EXPECT_TRUE(e.is_string()) << "summary.json: an effect is not a string";
  const Json* metrics = s.get("metrics");
  ASSERT_TRUE(metrics && metrics->kind == Json::Kind::object) << "summary.json: \"metrics\" is not an object";
  // a metric without a value is null and says why under "metrics_unreached"
  const Json* unreached = s.get("metrics_unreached");
  ASSERT_TRUE(unreached && unreached->kind == Json::Kind::object) << "summary.json: \"metrics_unreached\" is not an object";
  for (const auto& [k, v] : metrics->object) {
    if (v.kind == Json::Kind::null) {
      const Json* why = unreached->get(k);
      EXPECT_TRUE(why && why->is_string() && !why->string.empty())
          << "summary.json: metric " << k << " is null without a reason in metrics_unreached";
      continue;
    }
    EXPECT_TRUE(v.is_number() && std::isfinite(v.number)) << "summary.json: metric " << k << " is not a finite number";
  }
  for (const auto& [k, v] : unreached->object) {
    const Json* m = metrics->get(k);
    EXPECT_TRUE(m && m->kind == Json::Kind::null) << "summary.json: unreached metric " << k << " is not null in metrics";
  }
}

inline std::string summary_string(const Json& s, const std::string& key) {
  const Json* v = s.get(key);
  return v && v->is_string() ? v->string : std::string("<no string '" + key + "'>");
}
inline double summary_number(const Json& s, const std::string& key) {
  const Json* v = s.get(key);
  return v && v->is_number() ? v->number : std::nan("");
}

// ---- PNG read-back: the render tests' reader (same decoding, one copy) -----------------------

using ff::render::test::Image;
using ff::render::test::read_png;

/// A tmpfs of `kib` KiB mounted at `dir` for the scope; `why` says why not where it cannot be.
class SmallDisk {
 public:
  SmallDisk(const std::string& dir, int kib) : dir_(dir) {
    fs::create_directories(dir);
    const std::string opts = "size=" + std::to_string(kib) + "k";
    if (::mount("flexframe-test", dir.c_str(), "tmpfs", 0, opts.c_str()) == 0)
      mounted_ = true;
    else
      why_ = std::string("cannot mount a small tmpfs here (") + std::strerror(errno) + "; needs root)";
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }
  const std::string& why() const { return why_; }

 private:
  std::string dir_, why_;
  bool mounted_ = false;
};

}  // namespace ff::cli::test
