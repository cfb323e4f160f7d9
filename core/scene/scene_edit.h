#pragma once
/// \file scene_edit.h
/// Writing edited scenes back to TOML: a scene file's text with `--set`-style overrides folded
/// in, so an edit made in the GUI (or on the command line) can be saved as a scene of its own.

#include <optional>
#include <string>
#include <utility>
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
/// The same for a scene text held in memory (a scene being set up in the window); `path` names it
/// in messages. Throws SceneError when `text` + `overrides` do not validate.
std::string edited_scene_text(const std::string& text, const std::string& path, const std::vector<std::string>& overrides);

/// A value as --set reads it, as TOML text: TOML value syntax (0.01, true, "str", [1, 2]) as it is,
/// a bare word that is not TOML (efg) as a quoted string.
std::string toml_value_as_set_reads_it(const std::string& value);

// Structural edits of a scene text. Each keeps the text's comments and layout where it can, and
// checks that the result parses to exactly the edited TOML document; when it would not (an unusual
// layout), the whole document is written by the TOML library instead (comments lost, said in its
// first line). They do not validate against a schema: callers validate the result. A text that is
// not TOML is a SceneError at its line.

/// `text` with a new element of the array of tables [[array]] holding `keys` (name, TOML value
/// text), placed before element `before` (its header line), or after the last element when
/// `before` is absent or past the end.
std::string text_with_element(const std::string& text, const std::string& path, const std::string& array,
                              const std::vector<std::pair<std::string, std::string>>& keys,
                              std::optional<std::size_t> before = std::nullopt);
/// `text` without element `index` of [[array]] (its header, its keys and the comments inside it).
/// std::invalid_argument when there is no such element.
std::string text_without_element(const std::string& text, const std::string& path, const std::string& array,
                                 std::size_t index);
/// `text` without the keys named as --set names them ("part[0].polar_start", "solver.dt"); keys
/// the text does not have are skipped.
std::string text_without_keys(const std::string& text, const std::string& path, const std::vector<std::string>& keys);

}  // namespace ff::scene
