// The actions file of `flexframe gui --actions`: every verb parses, and a bad line is reported as
// FILE:LINE with what was expected.
#include <gtest/gtest.h>

#include "app/gui/actions.h"

namespace ff::app::gui {
namespace {

TEST(GuiActions, ParsesEveryVerb) {
  const std::string text =
      "# a comment\n"
      "\n"
      "run\n"
      "pause\n"
      "step\n"
      "step 25\n"
      "reset\n"
      "set solver.dt 0.01\n"
      "set material[0].thickness=0.02\n"
      "set scene.effects [\"inertia\", \"bending\"]\n"
      "wait 0.5\n"
      "screenshot out/shot.png\n"
      "probe 7\n"
      "save edited.toml\n"
      "export frame.png\n"
      "quit\n"
      "redraws\n";
  const std::vector<Action> a = parse_actions(text, "s.txt");
  ASSERT_EQ(a.size(), 15u);
  EXPECT_EQ(a[0].kind, Action::Kind::run);
  EXPECT_EQ(a[0].line, 3);
  EXPECT_EQ(a[2].kind, Action::Kind::step);
  EXPECT_EQ(a[2].count, 1);
  EXPECT_EQ(a[3].count, 25);
  EXPECT_EQ(a[5].key, "solver.dt");
  EXPECT_EQ(a[5].text, "0.01");
  EXPECT_EQ(a[6].key, "material[0].thickness");
  EXPECT_EQ(a[6].text, "0.02");
  EXPECT_EQ(a[7].text, "[\"inertia\", \"bending\"]");
  EXPECT_DOUBLE_EQ(a[8].seconds, 0.5);
  EXPECT_EQ(a[9].text, "out/shot.png");
  EXPECT_EQ(a[10].count, 7);
  EXPECT_EQ(a[11].kind, Action::Kind::save);
  EXPECT_EQ(a[12].kind, Action::Kind::export_png);
  EXPECT_EQ(a[13].kind, Action::Kind::quit);
  EXPECT_EQ(a[13].where(), "s.txt:16");
  EXPECT_EQ(a[14].kind, Action::Kind::redraws);
}

// The set-up verbs: entries, their fields (values with blanks inside [...] and "..."), picks.
TEST(GuiActions, ParsesTheSetUpVerbs) {
  const std::string text =
      "new static\n"
      "open assets/meshes/plate_4x4.obj\n"
      "add load type=force total=[0.0, 0.0, 1.0] label=\"tip force\"\n"
      "remove bc[2]\n"
      "preset material[1] CFRP ply (T300/5208)\n"
      "pick 3 4 17\n"
      "pick-box 10 20 300 400.5\n"
      "pick-clear\n"
      "use-pick probe[0]\n"
      "use-edge bc[0] plate x_min\n"
      "click 445 280\n"
      "show bc[1]\n"
      "show none\n"
      "wait-end\n"
      "metrics\n";
  const std::vector<Action> a = parse_actions(text, "s.txt");
  ASSERT_EQ(a.size(), 15u);
  EXPECT_EQ(a[0].kind, Action::Kind::new_problem);
  EXPECT_EQ(a[0].text, "static");
  EXPECT_EQ(a[1].text, "assets/meshes/plate_4x4.obj");
  EXPECT_EQ(a[2].key, "load");
  ASSERT_EQ(a[2].fields.size(), 3u);
  EXPECT_EQ(a[2].fields[1], (std::pair<std::string, std::string>{"total", "[0.0, 0.0, 1.0]"}));
  EXPECT_EQ(a[2].fields[2], (std::pair<std::string, std::string>{"label", "\"tip force\""}));
  EXPECT_EQ(a[3].key, "bc");
  EXPECT_EQ(a[3].count, 2);
  EXPECT_EQ(a[4].count, 1);
  EXPECT_EQ(a[4].text, "CFRP ply (T300/5208)");
  EXPECT_EQ(a[5].nodes, (std::vector<long long>{3, 4, 17}));
  EXPECT_EQ(a[6].pixels, (std::vector<double>{10, 20, 300, 400.5}));
  EXPECT_EQ(a[7].kind, Action::Kind::pick_clear);
  EXPECT_EQ(a[8].key, "probe");
  EXPECT_EQ(a[9].patch, "plate");
  EXPECT_EQ(a[9].edge, "x_min");
  EXPECT_EQ(a[10].pixels, (std::vector<double>{445, 280}));
  EXPECT_EQ(a[11].key, "bc");
  EXPECT_EQ(a[11].count, 1);
  EXPECT_EQ(a[12].text, "none");
  EXPECT_EQ(a[13].kind, Action::Kind::wait_end);
  EXPECT_EQ(a[14].kind, Action::Kind::metrics);
}

// `mode N` animates a mode of an eigen-analysis in the view, `mode off` returns to the run's frames
TEST(GuiActions, ParsesTheModeVerb) {
  const std::vector<Action> a = parse_actions("mode 2\nmode off\n", "s.txt");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].kind, Action::Kind::mode);
  EXPECT_EQ(a[0].count, 2);
  EXPECT_EQ(a[1].kind, Action::Kind::mode);
  EXPECT_EQ(a[1].count, 0);
}

TEST(GuiActions, BadLinesNameFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"run\njump\n", "s.txt:2: unknown action 'jump'"},
      {"step 0\n", "s.txt:1: 'step' takes a whole number of steps >= 1, got '0'"},
      {"step two\n", "s.txt:1: 'step'"},
      {"\n\nwait\n", "s.txt:3: 'wait' needs a number of seconds"},
      {"wait -1\n", "s.txt:1: 'wait'"},
      {"set solver.dt\n", "s.txt:1: 'set' needs a key and a value"},
      {"screenshot\n", "s.txt:1: 'screenshot' needs a file name"},
      {"probe -3\n", "s.txt:1: 'probe' needs a node index"},
      {"pause now\n", "s.txt:1: 'pause' takes no argument"},
      {"new modal\n", "s.txt:1: 'new' takes static or dynamic"},
      {"add\n", "s.txt:1: 'add' needs a table"},
      {"add bc clamped\n", "s.txt:1: 'add' takes KEY=VALUE after the table, got 'clamped'"},
      {"remove bc\n", "s.txt:1: 'remove' needs an entry"},
      {"remove bc[-1]\n", "s.txt:1: 'remove' needs an entry"},
      {"preset bc[0] steel\n", "s.txt:1: 'preset' needs a material entry"},
      {"pick\n", "s.txt:1: 'pick' needs node numbers"},
      {"pick 3 x\n", "s.txt:1: 'pick' takes node numbers >= 0, got 'x'"},
      {"click 10\n", "s.txt:1: 'click' needs X Y"},
      {"pick-box 1 2 3\n", "s.txt:1: 'pick-box' needs X0 Y0 X1 Y1"},
      {"use-edge bc[0] plate\n", "s.txt:1: 'use-edge' needs an entry, a patch and an edge"},
      {"show some\n", "s.txt:1: 'show' takes all, none or an entry"},
      {"view sideways\n", "s.txt:1: 'view' takes scene, iso, top, front or side"},
      {"mode 0\n", "s.txt:1: 'mode' takes a mode number >= 1 (animate it) or off"},
      {"mode second\n", "s.txt:1: 'mode' takes a mode number >= 1"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_actions(text, "s.txt");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ActionError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(read_actions("/nonexistent/actions.txt"), ActionError);
}

}  // namespace
}  // namespace ff::app::gui
