#pragma once
// Scratch files of a test: ${FF_BINARY_DIR}/test_out/<folder>/<name>, the folder made on first use.
#include <filesystem>
#include <fstream>
#include <string>

namespace ff::testing {

/// The path of `name` in the test's scratch folder `folder` (created when missing).
inline std::string scratch_path(const std::string& folder, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(FF_BINARY_DIR) / "test_out" / folder;
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

/// Writes `text` (bytes as given) to scratch_path(folder, name) and returns that path.
inline std::string write_scratch(const std::string& folder, const std::string& name, const std::string& text) {
  const std::string path = scratch_path(folder, name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace ff::testing
