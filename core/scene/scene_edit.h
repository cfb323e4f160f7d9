#pragma once
/// \file scene_edit.h
/// Writing edited scenes back to TOML: a scene file's text with `--set`-style overrides folded
/// in, so an edit made in the GUI (or on the command line) can be saved as a scene of its own.

#include <string>
#include <vector>

namespace ff::scene {

/// The text of the scene file `path` with `overrides` ("key=value", as for --set; later ones win)
/// written into it. Values the file has are replaced in place, so comments and layout stay; a key
/// the file lacks is added below its table's header (or in a new table at the end). Should the
/// patched text not read back to the same values (an unusual layout: dotted keys, inline tables),
/// the whole document is written out by the TOML library instead, without the comments.
/// The result always validates to the same values as `path` + `overrides`.
/// Throws SceneError when `path` + `overrides` do not validate.
std::string scene_text_with_overrides(const std::string& path, const std::vector<std::string>& overrides);

}  // namespace ff::scene
