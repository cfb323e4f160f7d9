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
