// app/output_folder.h (issue 30, findings 1 and 3): what a job may delete and when it may start.
// A job deletes only files an earlier job recorded, never through a symbolic link and never
// outside the folder, whatever the manifest says; a second job on a folder is refused.

#include <gtest/gtest.h>
#include <unistd.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>

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

// Issue 48, item 8: nothing is written through a link. A folder on the way to an output that is a
// link (or not a folder), and an output that is a symbolic link, a hard link or a FIFO, are
// refused with a WriteError that names the path; the link stays and its target is untouched.
std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(OutputFolder, NothingIsWrittenThroughALink) {
  const fs::path d = fresh_dir("links");
  const fs::path outside = fresh_dir("links_outside");
  std::ofstream(outside / "victim") << "precious\n";
  fs::create_directories(d / "out");
  fs::create_symlink(outside, d / "out" / "frames");
  fs::create_symlink(outside / "victim", d / "out" / "summary.json");
  fs::create_hard_link(outside / "victim", d / "out" / "results.h5");
  ASSERT_EQ(::mkfifo((d / "out" / "movie.mp4").c_str(), 0644), 0);
  OutputFolder f(d / "out", "run");
  const auto refused = [&](const std::function<void()>& write, const std::string& words) {
    try {
      write();
      ADD_FAILURE() << "not refused: " << words;
    } catch (const WriteError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("nothing was written through it"), std::string::npos) << e.what();
    }
  };
  refused([&] { f.sub_folder("frames"); }, "frames is a symbolic link");
  refused([&] { f.file("frames/frame_00000.png"); }, "frames is a symbolic link");
  refused([&] { f.sub_folder("frames/deeper"); }, "frames is a symbolic link");
  refused([&] { f.file("summary.json"); }, "symbolic link");
  refused([&] { write_text_file(d / "out" / "summary.json", "x"); }, "symbolic link");
  refused([&] { f.file("results.h5"); }, "hard link");
  refused([&] { f.file("movie.mp4"); }, "not a regular file");
  EXPECT_EQ(text_of(outside / "victim"), "precious\n");
  EXPECT_TRUE(fs::is_symlink(d / "out" / "frames"));
  EXPECT_TRUE(fs::is_symlink(d / "out" / "summary.json"));
  EXPECT_EQ(std::distance(fs::directory_iterator(outside), fs::directory_iterator()), 1) << "a file was made outside";
  // a temporary planted as a link is refused too, not followed
  std::ofstream(d / "out" / "plain.json") << "old\n";
  fs::create_symlink(outside / "victim", d / "out" / "plain.json.tmp");
  refused([&] { write_text_file(d / "out" / "plain.json", "new\n"); }, "symbolic link");
  EXPECT_EQ(text_of(outside / "victim"), "precious\n");
  EXPECT_EQ(text_of(d / "out" / "plain.json"), "old\n");
}

TEST(OutputFolder, ALinkAtItsOwnFilesIsRefusedWhenClaimed) {
  const fs::path outside = fresh_dir("own_outside");
  std::ofstream(outside / "victim") << "precious\n";
  for (const char* own : {".flexframe.lock", ".flexframe-reserve", ".flexframe-files", ".flexframe-files.tmp"}) {
    SCOPED_TRACE(own);
    const fs::path d = fresh_dir("own_links");
    fs::create_symlink(outside / "victim", d / own);
    EXPECT_THROW(OutputFolder(d, "run"), WriteError);
    EXPECT_EQ(text_of(outside / "victim"), "precious\n");
    EXPECT_TRUE(fs::is_symlink(d / own));
  }
}

}  // namespace
}  // namespace ff::app
