#pragma once
/// \file node_selection.h
/// Node sets chosen in a scene by geometric predicates (core/mesh/node_sets.h): the schema keys
/// of a selector inside any table (array) and the node ids they select, with located errors.
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"
#include "core/scene/schema.h"

namespace ff::scene {

/// Declares <table>.select, .point, .normal, .box_min, .box_max, .radius, .patch, .edge, .group,
/// .tolerance, .side. Edges are named as the generators name them (or u=0, u=1, v=0, v=1) in every model.
void declare_selector_keys(Schema& s, const std::string& table);
/// Node ids of mesh `m` chosen by entry i of `table`; SceneError at <table>.select when empty.
std::vector<int> select_nodes(const Document& d, const mesh::ShellMesh& m, const std::string& table, std::size_t i);
/// The quads entry i of `table` acts on, given its nodes `ids`: a surface group's own quads for
/// select = "group", else quads_within(m, ids).
std::vector<int> selected_quads(const Document& d, const mesh::ShellMesh& m, const std::string& table, std::size_t i,
                                const std::vector<int>& ids);
/// Quads of `m` whose 4 corner nodes are all in `ids` (ascending quad numbers).
std::vector<int> quads_within(const mesh::ShellMesh& m, const std::vector<int>& ids);
/// Shares of a total among nodes by tributary length along the line they lie on (trapezoid rule).
std::vector<double> tributary_weights(const mesh::ShellMesh& m, const std::vector<int>& ids);

}  // namespace ff::scene
