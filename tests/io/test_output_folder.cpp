// app/output_folder.h (issue 30, findings 1 and 3): what a job may delete and when it may start.
// A job deletes only files an earlier job recorded, never through a symbolic link and never
// outside the folder, whatever the manifest says; a second job on a folder is refused.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "app/output_folder.h"

namespace ff::app {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(FF_BINARY_DIR) / "test_out" / "output_folder" / name;
  std::error_code ec;
  fs::remove_all(d, ec);
  fs::create_directories(d);
  return d;
}

void touch(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "x";
}

TEST(OutputFolder, DeletesOnlyWhatAnEarlierJobRecorded) {
  const fs::path d = fresh_dir("recorded");
  {
    OutputFolder f(d, "run");
    f.sub_folder("frames");
    touch(f.file("frames/frame_00000.png"));
    touch(f.file("frames/frame_00001.png"));
  }
  touch(d / "frames" / "mine.png");  // the user's, never recorded
  OutputFolder f(d, "run");
  EXPECT_EQ(f.unrecorded_files("frames", ".png"), 1u);
  EXPECT_EQ(f.remove_earlier("frames/"), 2u);
  EXPECT_FALSE(fs::exists(d / "frames" / "frame_00000.png"));
  EXPECT_TRUE(fs::exists(d / "frames" / "mine.png"));
  EXPECT_TRUE(fs::is_directory(d / "frames")) << "a folder that still holds a user's file stays";
}

TEST(OutputFolder, AManifestCannotReachOutsideOrThroughALink) {
  const fs::path d = fresh_dir("hostile");
  const fs::path outside = fresh_dir("hostile_outside");
  touch(outside / "victim.png");
  touch(outside / "linked" / "frame.png");
  fs::create_directories(d / "frames");
  fs::create_directory_symlink(outside / "linked", d / "frames" / "sub");
  // a planted manifest naming files outside the folder and behind the link
  std::ofstream(d / ".flexframe-files") << "../hostile_outside/victim.png\n" << (outside / "victim.png").string()
                                        << "\nframes/sub/frame.png\nframes/../../hostile_outside/victim.png\n";
  OutputFolder f(d, "run");
  EXPECT_EQ(f.remove_earlier(""), 0u);
  EXPECT_TRUE(fs::exists(outside / "victim.png"));
  EXPECT_TRUE(fs::exists(outside / "linked" / "frame.png"));
}

TEST(OutputFolder, ASecondJobIsRefusedAndNamesTheFirst) {
  const fs::path d = fresh_dir("locked");
  OutputFolder first(d, "run");
  try {
    OutputFolder second(d, "study");
    FAIL() << "a second job took a locked folder";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("in use by flexframe run (pid " + std::to_string(::getpid()) + ")"), std::string::npos) << what;
  }
}

TEST(OutputFolder, TheReserveIsHeldUntilReleased) {
  const fs::path d = fresh_dir("reserve");
  OutputFolder f(d, "run");
  ASSERT_TRUE(fs::exists(d / ".flexframe-reserve"));
  EXPECT_EQ(fs::file_size(d / ".flexframe-reserve"), OutputFolder::kReserveBytes);
  f.release_reserve();
  EXPECT_FALSE(fs::exists(d / ".flexframe-reserve"));
}

TEST(WriteTextFile, ReplacesTheFileWhole) {
  const fs::path d = fresh_dir("text");
  write_text_file(d / "a.json", "first\n");
  write_text_file(d / "a.json", "second\n");
  std::ifstream in(d / "a.json");
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(s, "second\n");
  EXPECT_FALSE(fs::exists(d / "a.json.tmp"));
  EXPECT_THROW(write_text_file(d / "missing" / "a.json", "x"), WriteError);
}

}  // namespace
}  // namespace ff::app
