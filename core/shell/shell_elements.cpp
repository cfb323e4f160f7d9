#include "core/shell/shell_elements.h"

#include "core/assembly/node_frames.h"

namespace ff::shell {

void ShellElements::add_mesh(const mesh::ShellMesh& m, int node_offset, const std::vector<ShellSection>& sections,
                             const std::vector<ShellOptions>& options, const std::vector<double>& densities,
                             int part, const std::vector<Vec3>& reference_directions) {
  elements_.reserve(elements_.size() + m.quad_count());
  for (int q = 0; q < m.quad_count(); ++q) {
    const ShellSection& shared = sections.size() == 1 ? sections[0] : sections.at(q);
    // a per-quad copy only when directions are given: an isotropic structure without them builds
    // its elements from the very section it always did
    ShellSection directed;
    if (!reference_directions.empty()) directed = shared, directed.reference_direction = reference_directions.at(q);
    const ShellSection& section = reference_directions.empty() ? shared : directed;
    const ShellOptions& opt = options.size() == 1 ? options[0] : options.at(q);
    const double density = densities.size() == 1 ? densities[0] : densities.at(q);
    ShellElement e;
    e.part = part;
    e.thickness = section.thickness;
    ElementPoses ref;
    for (int c = 0; c < 4; ++c) {
      const int I = m.quads[q][c];
      e.nodes[c] = node_offset + I;
      const Vec3 nc = q < static_cast<int>(m.corner_normals.size()) ? m.corner_normals[q][c] : m.normals[I];
      // a fold corner has its own director; C maps node-local increments to corner-local ones
      const assembly::CornerFrame corner = assembly::corner_frame(m.frames[I], nc);
      e.corner[c] = corner.turn;
      e.plain = e.plain && (e.corner[c] - Mat3::Identity()).norm() < 1e-14;
      ref[c] = {corner.frame, m.points[I]};
    }
    try {
      e.elastic = std::make_unique<CbShellElement>(ref, section, opt);
    } catch (const std::invalid_argument& err) {
      // a quad that forms with a far thinner section is one whose thickness its curvature cannot
      // take; one that does not is degenerate in its own mid-surface (the mesh is at fault)
      ShellSection thin = section;
      thin.thickness *= 1e-6;
      bool forms_thin = true;
      try {
        CbShellElement probe(ref, thin, opt);
      } catch (const std::invalid_argument&) {
        forms_thin = false;
      }
      throw ShellElementError(q, part, forms_thin, "quad " + std::to_string(q) + ": " + err.what());
    }
    if (density > 0) e.inertia = std::make_unique<CbShellInertia>(ref, section, density);  // plies: (L10)
    elements_.push_back(std::move(e));
  }
}

}  // namespace ff::shell
