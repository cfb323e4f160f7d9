#include "app/gui/actions.h"

#include "core/frame/text.h"
#include "core/frame/input_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cctype>
#include <sstream>

namespace ff::app::gui {
namespace {

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
                               "probe NODE, save FILE, export FILE, redraws, quit, new static|dynamic, open FILE, "
                               "add TABLE [KEY=VALUE ...], remove TABLE[I], preset material[I] NAME, pick NODE..., "
                               "pick-box X0 Y0 X1 Y1, pick-clear, use-pick TABLE[I], use-edge TABLE[I] PATCH EDGE, click X Y, show all|none|TABLE[I], wait-end, metrics, view scene|iso|top|front|side, mode N|off";

/// "bc[2]" -> ("bc", 2); false when it is not NAME[INDEX].
bool parse_entry(const std::string& s, std::string* table, long long* index) {
  const auto lb = s.find('[');
  if (lb == std::string::npos || lb == 0 || s.back() != ']') return false;
  *table = s.substr(0, lb);
  for (char c : *table)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return parse_int(s.substr(lb + 1, s.size() - lb - 2), index) && *index >= 0;
}

/// Splits at blanks outside [...] and "...": `type=force point=[1, 0, 0]` -> 2 words.
std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  bool quoted = false;
  for (char c : s) {
    if (c == '"') quoted = !quoted;
    if (!quoted && c == '[') ++depth;
    if (!quoted && c == ']') --depth;
    if (!quoted && depth <= 0 && (c == ' ' || c == '\t')) {
      if (!cur.empty()) out.push_back(cur), cur.clear();
      continue;
    }
    cur += c;
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

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
    } else if (verb == "new") {
      a.kind = Action::Kind::new_problem;
      if (rest != "static" && rest != "dynamic") fail("'new' takes static or dynamic: new static");
      a.text = rest;
    } else if (verb == "open") {
      a.kind = Action::Kind::open, need_path();
    } else if (verb == "add") {
      a.kind = Action::Kind::add;
      const std::vector<std::string> w = words(rest);
      if (w.empty()) fail("'add' needs a table: add TABLE [KEY=VALUE ...] (e.g. add bc type=clamped)");
      a.key = w[0];
      for (std::size_t k = 1; k < w.size(); ++k) {
        const auto eq = w[k].find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == w[k].size())
          fail("'add' takes KEY=VALUE after the table, got '" + w[k] + "'");
        a.fields.emplace_back(w[k].substr(0, eq), w[k].substr(eq + 1));
      }
    } else if (verb == "remove" || verb == "use-pick") {
      a.kind = verb == "remove" ? Action::Kind::remove : Action::Kind::use_pick;
      if (!parse_entry(rest, &a.key, &a.count)) fail("'" + verb + "' needs an entry: " + verb + " TABLE[I] (e.g. bc[0])");
    } else if (verb == "use-edge") {
      a.kind = Action::Kind::use_edge;
      const std::vector<std::string> w = words(rest);
      if (w.size() != 3 || !parse_entry(w[0], &a.key, &a.count))
        fail("'use-edge' needs an entry, a patch and an edge: use-edge bc[0] plate x_min");
      a.patch = w[1], a.edge = w[2];
    } else if (verb == "preset") {
      a.kind = Action::Kind::preset;
      const auto ws = rest.find_first_of(" \t");
      const std::string entry = rest.substr(0, ws);
      a.text = ws == std::string::npos ? "" : trim(rest.substr(ws));
      if (!parse_entry(entry, &a.key, &a.count) || a.key != "material" || a.text.empty())
        fail("'preset' needs a material entry and a preset name: preset material[0] steel");
    } else if (verb == "pick") {
      a.kind = Action::Kind::pick;
      for (const std::string& w : words(rest)) {
        long long n = 0;
        if (!parse_int(w, &n) || n < 0) fail("'pick' takes node numbers >= 0, got '" + w + "'");
        a.nodes.push_back(n);
      }
      if (a.nodes.empty()) fail("'pick' needs node numbers: pick NODE...");
    } else if (verb == "view") {
      a.kind = Action::Kind::view;
      if (rest != "scene" && rest != "iso" && rest != "top" && rest != "front" && rest != "side")
        fail("'view' takes scene, iso, top, front or side (as the view buttons)");
      a.text = rest;
    } else if (verb == "wait-end") {
      a.kind = Action::Kind::wait_end, no_args();
    } else if (verb == "metrics") {
      a.kind = Action::Kind::metrics, no_args();
    } else if (verb == "mode") {
      a.kind = Action::Kind::mode;
      if (rest == "off")
        a.count = 0;
      else if (!parse_int(rest, &a.count) || a.count < 1)
        fail("'mode' takes a mode number >= 1 (animate it) or off: mode 2");
    } else if (verb == "pick-clear") {
      a.kind = Action::Kind::pick_clear, no_args();
    } else if (verb == "click" || verb == "pick-box") {
      a.kind = verb == "click" ? Action::Kind::click : Action::Kind::pick_box;
      const std::size_t want = verb == "click" ? 2 : 4;
      for (const std::string& w : words(rest)) {
        double v = 0;
        if (!parse_number(w, &v) || v < 0) fail("'" + verb + "' takes pixel coordinates >= 0, got '" + w + "'");
        a.pixels.push_back(v);
      }
      if (a.pixels.size() != want)
        fail(verb == "click" ? "'click' needs X Y: click 400 300" : "'pick-box' needs X0 Y0 X1 Y1: pick-box 100 100 300 250");
    } else if (verb == "show") {
      a.kind = Action::Kind::show;
      if (rest == "all" || rest == "none")
        a.text = rest;
      else if (!parse_entry(rest, &a.key, &a.count))
        fail("'show' takes all, none or an entry: show bc[0]");
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
  std::string text, problem;
  if (!read_input_file(path, &text, kMaxTextInputBytes, kTextInputBound, &problem))
    throw ActionError("the actions file '" + path + "' " + problem);
  return parse_actions(text, path);
}

}  // namespace ff::app::gui
