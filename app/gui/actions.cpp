#include "app/gui/actions.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ff::app::gui {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

bool parse_int(const std::string& s, long long* out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (errno != 0 || *end != '\0') return false;
  *out = v;
  return true;
}

bool parse_number(const std::string& s, double* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (*end != '\0' || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

constexpr const char* kVerbs = "run, pause, step [N], reset, set KEY VALUE, wait SECONDS, screenshot FILE, "
                               "probe NODE, save FILE, export FILE, redraws, quit";

}  // namespace

std::vector<Action> parse_actions(const std::string& text, const std::string& file_name) {
  std::vector<Action> actions;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#') continue;
    Action a;
    a.file = file_name;
    a.line = line_no;
    const auto fail = [&](const std::string& msg) { throw ActionError(a.where() + ": " + msg); };
    const auto sp = line.find_first_of(" \t");
    const std::string verb = line.substr(0, sp);
    const std::string rest = sp == std::string::npos ? "" : trim(line.substr(sp));
    const auto no_args = [&] {
      if (!rest.empty()) fail("'" + verb + "' takes no argument, got '" + rest + "'");
    };
    const auto need_path = [&] {
      if (rest.empty()) fail("'" + verb + "' needs a file name: " + verb + " FILE");
      a.text = rest;
    };
    if (verb == "run") {
      a.kind = Action::Kind::run, no_args();
    } else if (verb == "pause") {
      a.kind = Action::Kind::pause, no_args();
    } else if (verb == "reset") {
      a.kind = Action::Kind::reset, no_args();
    } else if (verb == "redraws") {
      a.kind = Action::Kind::redraws, no_args();
    } else if (verb == "quit") {
      a.kind = Action::Kind::quit, no_args();
    } else if (verb == "step") {
      a.kind = Action::Kind::step;
      if (!rest.empty() && (!parse_int(rest, &a.count) || a.count < 1))
        fail("'step' takes a whole number of steps >= 1, got '" + rest + "'");
    } else if (verb == "probe") {
      a.kind = Action::Kind::probe;
      if (!parse_int(rest, &a.count) || a.count < 0)
        fail("'probe' needs a node index >= 0: probe NODE" + (rest.empty() ? "" : ", got '" + rest + "'"));
    } else if (verb == "wait") {
      a.kind = Action::Kind::wait;
      if (!parse_number(rest, &a.seconds) || a.seconds < 0)
        fail("'wait' needs a number of seconds >= 0: wait SECONDS" + (rest.empty() ? "" : ", got '" + rest + "'"));
    } else if (verb == "set") {
      a.kind = Action::Kind::set;
      const auto ksp = rest.find_first_of(" \t=");
      a.key = rest.substr(0, ksp);
      std::string value = ksp == std::string::npos ? "" : trim(rest.substr(ksp));
      if (!value.empty() && value[0] == '=') value = trim(value.substr(1));  // set KEY=VALUE works too
      if (a.key.empty() || value.empty()) fail("'set' needs a key and a value: set KEY VALUE (e.g. set solver.dt 0.01)");
      a.text = value;
    } else if (verb == "screenshot") {
      a.kind = Action::Kind::screenshot, need_path();
    } else if (verb == "save") {
      a.kind = Action::Kind::save, need_path();
    } else if (verb == "export") {
      a.kind = Action::Kind::export_png, need_path();
    } else {
      fail("unknown action '" + verb + "'; one of: " + kVerbs);
    }
    actions.push_back(a);
  }
  return actions;
}

std::vector<Action> read_actions(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ActionError(path + ": cannot read the actions file");
  std::stringstream s;
  s << in.rdbuf();
  return parse_actions(s.str(), path);
}

}  // namespace ff::app::gui
