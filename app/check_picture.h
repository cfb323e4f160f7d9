#pragma once
/// \file check_picture.h
/// `flexframe check SCENE --picture FILE.png`: the scene's shell structure drawn with what its names
/// select, coloured and labelled (render/mesh_picture.h), so a user sees what the supports, loads
/// and probes act on before running: the parts (when there are several), the mesh's named groups,
/// and the nodes of every [[bc]], [[load]], [[probe]], [[joint]] and [[arc]] entry.

#include <string>
#include <vector>

#include "core/scene/scene_context.h"
#include "core/scene/scene_selections.h"
#include "render/mesh_picture.h"

namespace ff::app {

/// The picture of a scene's selections (plain arrays for render/): the patches in pale colours
/// when there are several (parts, or l_plate's arm1, corner, arm2: what select = "patch_edge"
/// names), then the mesh's named groups and the scene's entries in strong colours, each
/// labelled at its node nearest the centroid of its nodes (an entry as its legend line, e.g.
/// "bc[0] clamped (33 nodes)", or as "bc[0]" alone when more than 12 groups and entries crowd the
/// picture).
render::MeshPicture selections_picture(const scene::SceneSelections& s);

/// Refuses (InputError) a picture path that is empty, does not end in .png, names a folder, or lies
/// in a folder that does not exist: the picture goes exactly where the user asked, or nowhere.
void check_picture_path(const std::string& png_path);

/// Reads the scene's selections and writes the picture to png_path (which must end in .png, in a
/// folder that exists). Returns the line `check` prints, e.g. "picture: roof.png (1280x960): 1 part,
/// 0 named groups, 3 selections". Throws InputError for a path it may not write or a model
/// without a shell structure, SceneError as load_scene does, std::runtime_error when drawing or
/// writing fails (nothing is left at png_path then).
std::string write_check_picture(const std::string& scene_path, const std::vector<std::string>& overrides,
                                const std::string& png_path, const scene::SceneContext& ctx);

}  // namespace ff::app
