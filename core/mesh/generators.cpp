#include "core/mesh/generators.h"

#include "core/frame/text.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace ff::mesh {

namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(what); }

void require_counts(const std::string& who, int n1, int n2) {
  if (n1 < 1 || n2 < 1)
    fail(who + ": element counts must be at least 1 (got " + std::to_string(n1) + " x " + std::to_string(n2) + ")");
}

void require_positive(const std::string& who, const char* what, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) fail(who + ": " + what + " must be positive and finite (got " + std::to_string(v) + ")");
}

void require_range(const std::string& who, const char* what, double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || a == b)
    fail(who + ": " + what + " range [" + std::to_string(a) + ", " + std::to_string(b) + "] is empty");
}

void require_angle_span(const std::string& who, const char* what, double a, double b) {
  require_range(who, what, a, b);
  if (std::abs(b - a) > kTwoPi * (1 + 1e-12))
    fail(who + ": " + what + " range [" + std::to_string(a) + ", " + std::to_string(b) + "] exceeds 2 pi");
}

Vec3 unit(const std::string& who, const char* what, const Vec3& v) {
  const double n = v.norm();
  if (!(n > 0.0) || !std::isfinite(n)) fail(who + ": " + what + " must be a non-zero finite vector");
  return v / n;
}

// component of `radial` orthogonal to the unit `axis`, normalized
Vec3 orthogonal_unit(const std::string& who, const Vec3& axis, const Vec3& radial) {
  const Vec3 r = radial - radial.dot(axis) * axis;
  if (r.norm() < 1e-9 * std::max(1.0, radial.norm()))
    fail(who + ": the phi = 0 direction is parallel to the axis; choose a radial0 orthogonal to it");
  return r.normalized();
}

double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// hash grid over cells of size `cell` for the coincident-node search
struct CellKey {
  std::int64_t i, j, k;
  bool operator==(const CellKey&) const = default;
};
struct CellHash {
  std::size_t operator()(const CellKey& c) const {
    std::uint64_t h = static_cast<std::uint64_t>(c.i) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(c.j) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(c.k) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};
std::int64_t cell_of(double x, double cell) {
  const double c = std::floor(x / cell);
  if (std::isnan(c)) return 0;  // NaN has no cell (and casting it is undefined); validate() refuses it
  return static_cast<std::int64_t>(std::clamp(c, -4e18, 4e18));
}

}  // namespace

ShellMesh parametric_patch(const std::string& name, const std::string& description, int nu, int nv,
                           const SurfaceMap& map, bool merge_seam) {
  require_counts("patch '" + name + "'", nu, nv);
  ShellMesh m;
  const std::size_t nn = static_cast<std::size_t>(nu + 1) * (nv + 1);
  m.points.reserve(nn);
  m.normals.reserve(nn);
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const SurfacePoint p = map(static_cast<double>(i) / nu, static_cast<double>(j) / nv);
      const double len = p.n.norm();
      if (!p.x.allFinite() || !(len > 0.0) || !std::isfinite(len))
        fail("patch '" + name + "': the surface map gives no finite point/normal at node (" + std::to_string(i) + ", " +
             std::to_string(j) + ")");
      m.points.push_back(p.x);
      m.normals.push_back(p.n / len);
    }
  auto id = [nu](int i, int j) { return j * (nu + 1) + i; };
  // counter-clockwise about the normal: decide once from the central quad's x_u x x_v
  const int ic = nu / 2, jc = nv / 2;
  const std::array<int, 4> c0{id(ic, jc), id(ic + 1, jc), id(ic + 1, jc + 1), id(ic, jc + 1)};
  const Vec3 g = (m.points[c0[2]] - m.points[c0[0]]).cross(m.points[c0[3]] - m.points[c0[1]]);
  Vec3 nsum = Vec3::Zero();
  for (int k : c0) nsum += m.normals[k];
  const bool reverse = g.dot(nsum) < 0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      if (reverse) m.quads.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
      else m.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  Patch p;
  p.name = name;
  p.description = description;
  p.nu = nu;
  p.nv = nv;
  p.grid.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) p.grid[k] = static_cast<int>(k);
  p.first_quad = 0;
  p.quad_count = m.quad_count();
  m.patches.push_back(std::move(p));
  m.quad_patch.assign(m.quads.size(), 0);
  m.fold.assign(m.points.size(), 0);
  corner_normals_from_nodes(m);
  compute_frames(m);
  // a closed patch (360 degree cylinder, full annulus) merges its seam here; a slit keeps it
  if (!merge_seam) return m;
  return assemble({m});
}

ShellMesh rectangular_plate(const RectangularPlate& s, int n_a, int n_b, const std::string& name) {
  const std::string who = "rectangular plate '" + name + "'";
  require_positive(who, "length a", s.a);
  require_positive(who, "width b", s.b);
  const Vec3 ea = unit(who, "e_a", s.e_a), eb = unit(who, "e_b", s.e_b);
  if (std::abs(ea.dot(eb)) > 1e-9) fail(who + ": e_a and e_b must be orthogonal");
  const Vec3 n = ea.cross(eb);
  const Vec3 o = s.origin;
  const double a = s.a, b = s.b;
  return parametric_patch(name, "plate " + significant(a) + " x " + significant(b), n_a, n_b, [=](double u, double v) {
    return SurfacePoint{o + (u * a) * ea + (v * b) * eb, n};
  });
}

ShellMesh rectangular_plate(double a, double b, int n_a, int n_b, const std::string& name) {
  RectangularPlate s;
  s.a = a;
  s.b = b;
  return rectangular_plate(s, n_a, n_b, name);
}

ShellMesh axis_aligned_plate(double a, double b, const Vec3& origin, int n_a, int n_b, const std::string& name) {
  if (!origin.allFinite()) fail("rectangular plate '" + name + "': the origin must be finite");
  RectangularPlate s;
  s.a = a;
  s.b = b;
  s.origin = origin;
  ShellMesh m = rectangular_plate(s, n_a, n_b, name);
  m.patches[0].edge_names = {"x_min", "x_max", "y_min", "y_max"};
  return m;
}

ShellMesh cylindrical_patch(const CylinderPatch& s, int n_phi, int n_axial, const std::string& name) {
  const std::string who = "cylindrical patch '" + name + "'";
  require_positive(who, "radius", s.radius);
  require_angle_span(who, "phi", s.phi0, s.phi1);
  require_range(who, "axial", s.s0, s.s1);
  const Vec3 ax = unit(who, "axis", s.axis);
  const Vec3 r0 = orthogonal_unit(who, ax, s.radial0);
  const Vec3 et = ax.cross(r0);
  const double R = s.radius, p0 = s.phi0, dp = s.phi1 - s.phi0, z0 = s.s0, dz = s.s1 - s.s0;
  const double sign = s.outward ? 1.0 : -1.0;
  const Vec3 o = s.origin;
  const std::string d = "cylinder R=" + significant(R) + ", phi in [" + significant(s.phi0) + ", " + significant(s.phi1) + "] rad, axial in [" +
                        significant(s.s0) + ", " + significant(s.s1) + "]";
  ShellMesh m = parametric_patch(
      name, d, n_phi, n_axial,
      [=](double u, double v) {
        const double phi = p0 + u * dp;
        const Vec3 radial = std::cos(phi) * r0 + std::sin(phi) * et;
        return SurfacePoint{o + (z0 + v * dz) * ax + R * radial, sign * radial};
      },
      !s.slit);
  m.patches[0].edge_names = {"start_angle", "end_angle", "bottom", "top"};
  return m;
}

ShellMesh spherical_patch(const SpherePatch& s, int n_theta, int n_phi, const std::string& name) {
  const std::string who = "spherical patch '" + name + "'";
  require_positive(who, "radius", s.radius);
  require_range(who, "theta", s.theta0, s.theta1);
  require_angle_span(who, "phi", s.phi0, s.phi1);
  const double tmin = std::min(s.theta0, s.theta1), tmax = std::max(s.theta0, s.theta1);
  if (tmin <= 1e-9 || tmax >= std::numbers::pi - 1e-9)
    fail(who + ": theta range [" + significant(s.theta0) + ", " + significant(s.theta1) +
         "] touches a pole, where quads collapse to triangles; leave a polar hole (0 < theta < pi)");
  const Vec3 pole = unit(who, "pole", s.pole);
  const Vec3 r0 = orthogonal_unit(who, pole, s.radial0);
  const Vec3 et = pole.cross(r0);
  const double R = s.radius, t0 = s.theta0, dt = s.theta1 - s.theta0, p0 = s.phi0, dp = s.phi1 - s.phi0;
  const double sign = s.outward ? 1.0 : -1.0;
  const Vec3 c = s.center;
  const std::string d = "sphere R=" + significant(R) + ", theta in [" + significant(s.theta0) + ", " + significant(s.theta1) +
                        "] rad, phi in [" + significant(s.phi0) + ", " + significant(s.phi1) + "] rad";
  ShellMesh m = parametric_patch(name, d, n_theta, n_phi, [=](double u, double v) {
    const double th = t0 + u * dt, ph = p0 + v * dp;
    const Vec3 radial = std::sin(th) * (std::cos(ph) * r0 + std::sin(ph) * et) + std::cos(th) * pole;
    return SurfacePoint{c + R * radial, sign * radial};
  });
  m.patches[0].edge_names = {"hole", "rim", "start_angle", "end_angle"};
  return m;
}

ShellMesh annular_sector(const AnnularSector& s, int n_r, int n_phi, const std::string& name) {
  const std::string who = "annular sector '" + name + "'";
  require_positive(who, "inner radius", s.r_inner);
  require_positive(who, "outer radius", s.r_outer);
  require_range(who, "radius", s.r_inner, s.r_outer);
  require_angle_span(who, "phi", s.phi0, s.phi1);
  const Vec3 ax = unit(who, "axis", s.axis);
  const Vec3 r0 = orthogonal_unit(who, ax, s.radial0);
  const Vec3 et = ax.cross(r0);
  const double ra = s.r_inner, dr = s.r_outer - s.r_inner, p0 = s.phi0, dp = s.phi1 - s.phi0;
  const Vec3 c = s.center;
  const std::string d = "annular sector r in [" + significant(s.r_inner) + ", " + significant(s.r_outer) + "], phi in [" +
                        significant(s.phi0) + ", " + significant(s.phi1) + "] rad";
  ShellMesh m = parametric_patch(
      name, d, n_r, n_phi,
      [=](double u, double v) {
        const double r = ra + u * dr, ph = p0 + v * dp;
        return SurfacePoint{c + r * (std::cos(ph) * r0 + std::sin(ph) * et), ax};
      },
      !s.slit);
  m.patches[0].edge_names = {"inner", "outer", "start_angle", "end_angle"};
  return m;
}

ShellMesh polar_o_grid(const std::string& name, const std::string& description, const std::string& rim_name,
                       double phi0, double phi1, int n_ring, int n_rim, const PolarMap& map) {
  const std::string who = "polar mesh '" + name + "'";
  require_counts(who, n_ring, n_rim);
  require_angle_span(who, "phi", phi0, phi1);
  const double span = std::abs(phi1 - phi0), sense = phi1 > phi0 ? 1.0 : -1.0;
  // quadrants the span covers: the core is a quarter (1), half (2) or whole (4) square
  int quadrants = 0;
  for (int q : {1, 2, 4})
    if (std::abs(span - q * std::numbers::pi / 2) <= 1e-9 * kTwoPi) quadrants = q;
  if (quadrants == 0)
    fail(who + ": a region that contains its pole (no hole) must span 90, 180 or 360 degrees of azimuth (got " +
         significant(span * 180 / std::numbers::pi) + " deg); leave a hole or split the region");
  if (n_rim % (2 * quadrants) != 0)
    fail(who + ": the elements along the rim (" + std::to_string(n_rim) + ") must be a multiple of " +
         std::to_string(2 * quadrants) + " for a " + significant(90.0 * quadrants) +
         " degree region without a hole (the core square takes n/" + std::to_string(2 * quadrants) +
         " elements per half-side)");
  const int m = n_rim / (2 * quadrants);  // core elements per half-side
  const double a = std::clamp(static_cast<double>(m) / (m + n_ring), 0.25, 0.6);
  // flat core rectangle [x_lo, a] x [y_lo, a] in the frame whose x axis points at phi0
  const double x_lo = quadrants >= 2 ? -a : 0.0, y_lo = quadrants == 4 ? -a : 0.0;
  const int nx = quadrants >= 2 ? 2 * m : m, ny = quadrants == 4 ? 2 * m : m;
  auto surface = [&, phi0, sense](double x, double y) {
    const double rho = std::hypot(x, y);
    const double angle = rho > 0 ? std::atan2(y, x) : 0.0;
    // the whole disk: angles in [-pi, pi) relative to phi0 are the same points
    return map(rho, phi0 + sense * angle);
  };
  ShellMesh core = parametric_patch(name + "_core", description + " (core around the pole)", nx, ny,
                                    [&](double u, double v) { return surface(x_lo + u * (a - x_lo), y_lo + v * (a - y_lo)); });
  // the core outline from angle 0 to the span, counter-clockwise in the flat frame; its corners
  // are nodes, and node k of it faces the rim node at angle k * span / n_rim
  std::vector<Eigen::Vector2d> corners;
  corners.emplace_back(a, 0.0);
  corners.emplace_back(a, a);
  if (quadrants == 1) corners.emplace_back(0.0, a);
  else corners.emplace_back(-a, a), corners.emplace_back(-a, quadrants == 2 ? 0.0 : -a);
  if (quadrants == 4) corners.emplace_back(a, -a), corners.emplace_back(a, 0.0);
  std::vector<int> segment_elements;  // elements along each side of the outline
  for (std::size_t k = 0; k + 1 < corners.size(); ++k)
    segment_elements.push_back(static_cast<int>(std::lround((corners[k + 1] - corners[k]).norm() / a * m)));
  auto outline = [&](int node) {
    for (std::size_t k = 0; k < segment_elements.size(); ++k) {
      if (node <= segment_elements[k])
        return Eigen::Vector2d(corners[k] + (corners[k + 1] - corners[k]) * (static_cast<double>(node) / segment_elements[k]));
      node -= segment_elements[k];
    }
    return corners.back();
  };
  ShellMesh ring = parametric_patch(name, description, n_ring, n_rim, [&](double u, double v) {
    const int node = static_cast<int>(std::lround(v * n_rim));
    const double angle = static_cast<double>(node) / n_rim * span;
    const Eigen::Vector2d p = (1.0 - u) * outline(node) + u * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    if (u == 1.0) return map(1.0, phi0 + sense * angle);  // the rim exactly
    return surface(p.x(), p.y());
  });
  ring.patches[0].edge_names = {"core", rim_name, "", ""};
  return assemble({core, ring});
}

ShellMesh annulus(const AnnularSector& s, int n_r, int n_phi, const std::string& name) {
  if (s.r_inner != 0.0 || s.slit) return annular_sector(s, n_r, n_phi, name);
  const std::string who = "disk '" + name + "'";
  require_positive(who, "radius", s.r_outer);
  const Vec3 ax = unit(who, "axis", s.axis);
  const Vec3 r0 = orthogonal_unit(who, ax, s.radial0);
  const Vec3 et = ax.cross(r0);
  const double R = s.r_outer;
  const Vec3 c = s.center;
  const std::string d = "disk r <= " + significant(R) + ", phi in [" + significant(s.phi0) + ", " + significant(s.phi1) + "] rad";
  return polar_o_grid(name, d, "outer", s.phi0, s.phi1, n_r, n_phi, [=](double rho, double ph) {
    return SurfacePoint{c + (rho * R) * (std::cos(ph) * r0 + std::sin(ph) * et), ax};
  });
}

ShellMesh spherical_cap(const SpherePatch& s, int n_theta, int n_phi, const std::string& name) {
  if (s.theta0 != 0.0) return spherical_patch(s, n_theta, n_phi, name);
  const std::string who = "spherical cap '" + name + "'";
  require_positive(who, "radius", s.radius);
  if (!(s.theta1 > 0.0) || !(s.theta1 < std::numbers::pi - 1e-9))
    fail(who + ": the polar angle of the rim must lie in (0, pi) (got " + significant(s.theta1) +
         " rad); a cap reaching the opposite pole would collapse quads there");
  const Vec3 pole = unit(who, "pole", s.pole);
  const Vec3 r0 = orthogonal_unit(who, pole, s.radial0);
  const Vec3 et = pole.cross(r0);
  const double R = s.radius, t1 = s.theta1, sign = s.outward ? 1.0 : -1.0;
  const Vec3 c = s.center;
  const std::string d = "spherical cap R=" + significant(R) + ", theta <= " + significant(t1) + " rad, phi in [" + significant(s.phi0) + ", " +
                        significant(s.phi1) + "] rad";
  return polar_o_grid(name, d, "rim", s.phi0, s.phi1, n_theta, n_phi, [=](double rho, double ph) {
    const double th = rho * t1;
    const Vec3 radial = std::sin(th) * (std::cos(ph) * r0 + std::sin(ph) * et) + std::cos(th) * pole;
    return SurfacePoint{c + R * radial, sign * radial};
  });
}

ShellMesh assemble(const std::vector<ShellMesh>& parts, const AssemblyOptions& options) {
  // tolerance relative to the finest part
  double h = std::numeric_limits<double>::infinity();
  for (const auto& p : parts)
    if (!p.quads.empty()) h = std::min(h, min_edge_length(p));
  const double tol = std::isfinite(h) ? options.merge_tolerance * h : 0.0;
  const double cell = tol > 0 ? tol : 1.0;

  ShellMesh out;
  std::vector<int> offsets;
  std::vector<Vec3> all_points, all_normals;
  std::vector<std::uint8_t> all_fold;
  for (const auto& p : parts) {
    offsets.push_back(static_cast<int>(all_points.size()));
    for (int i = 0; i < p.node_count(); ++i) {
      all_points.push_back(p.points[i]);
      all_normals.push_back(p.normals.at(i));
      all_fold.push_back(i < static_cast<int>(p.fold.size()) ? p.fold[i] : 0);
    }
  }

  // first occurrence wins: new id in order of first appearance
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  std::vector<int> new_id(all_points.size(), -1);
  for (std::size_t i = 0; i < all_points.size(); ++i) {
    const Vec3& x = all_points[i];
    const CellKey c{cell_of(x.x(), cell), cell_of(x.y(), cell), cell_of(x.z(), cell)};
    int found = -1;
    for (int di = -1; di <= 1 && found < 0; ++di)
      for (int dj = -1; dj <= 1 && found < 0; ++dj)
        for (int dk = -1; dk <= 1 && found < 0; ++dk) {
          auto it = grid.find({c.i + di, c.j + dj, c.k + dk});
          if (it == grid.end()) continue;
          for (int r : it->second)
            if ((out.points[r] - x).norm() <= tol) {
              found = r;
              break;
            }
        }
    if (found >= 0) {
      new_id[i] = found;
      if (all_fold[i] || angle_between(out.normals[found], all_normals[i]) > options.fold_angle) out.fold[found] = 1;
    } else {
      new_id[i] = out.node_count();
      out.points.push_back(x);
      out.normals.push_back(all_normals[i]);
      out.fold.push_back(all_fold[i]);
      grid[c].push_back(new_id[i]);
    }
  }

  std::vector<std::string> names;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const ShellMesh& p = parts[k];
    const int off = offsets[k];
    const int patch_off = static_cast<int>(out.patches.size());
    const int quad_off = out.quad_count();
    for (int q = 0; q < p.quad_count(); ++q) {
      std::array<int, 4> c{};
      std::array<Vec3, 4> d;
      for (int l = 0; l < 4; ++l) {
        c[l] = new_id[off + p.quads[q][l]];
        d[l] = q < static_cast<int>(p.corner_normals.size()) ? p.corner_normals[q][l] : p.normals[p.quads[q][l]];
      }
      out.quads.push_back(c);
      out.corner_normals.push_back(d);
      out.quad_patch.push_back(patch_off + (q < static_cast<int>(p.quad_patch.size()) ? p.quad_patch[q] : 0));
    }
    std::vector<Patch> patches = p.patches;
    if (patches.empty()) {
      Patch whole;
      whole.name = "part" + std::to_string(k);
      whole.quad_count = p.quad_count();
      patches.push_back(whole);
    }
    for (Patch pp : patches) {
      for (int& g : pp.grid) g = new_id[off + g];
      pp.first_quad += quad_off;
      // unique names: "name", "name_2", "name_3", ...
      std::string base = pp.name, name = base;
      for (int n = 2; std::find(names.begin(), names.end(), name) != names.end(); ++n) name = base + "_" + std::to_string(n);
      pp.name = name;
      names.push_back(name);
      out.patches.push_back(std::move(pp));
    }
  }
  compute_frames(out, options.frame_reference);
  return out;
}

// ---- benchmarks -----------------------------------------------------------------------------

ShellMesh cantilever_strip(int n_length, int n_width) {
  return rectangular_plate(bench::kStripLength, bench::kStripWidth, n_length, n_width, "strip");
}

ShellMesh hemisphere_quarter(int n_theta, int n_phi) {
  SpherePatch s;
  s.radius = bench::kHemisphereRadius;
  s.theta0 = bench::kHemisphereHole;
  s.theta1 = std::numbers::pi / 2;
  s.phi0 = 0;
  s.phi1 = std::numbers::pi / 2;
  return spherical_patch(s, n_theta, n_phi, "hemisphere");
}

ShellMesh open_cylinder_octant(int n_phi, int n_axial) {
  CylinderPatch s;
  s.radius = bench::kCylinderRadius;
  s.axis = Vec3::UnitZ();
  s.radial0 = Vec3::UnitX();
  s.phi0 = 0;
  s.phi1 = std::numbers::pi / 2;
  s.s0 = 0;
  s.s1 = bench::kCylinderLength / 2;
  return cylindrical_patch(s, n_phi, n_axial, "cylinder");
}

ShellMesh hinged_roof_quarter(int n_arc, int n_axial) {
  CylinderPatch s;
  s.radius = bench::kRoofRadius;
  s.origin = Vec3(0, 0, -bench::kRoofRadius);
  s.axis = Vec3::UnitX();
  s.radial0 = Vec3::UnitZ();
  // axis x r0 = -y, so phi in [-theta, 0] runs from y = R sin(theta) to the crown y = 0
  s.phi0 = -bench::kRoofHalfAngle;
  s.phi1 = 0;
  s.s0 = 0;
  s.s1 = bench::kRoofHalfLength;
  return cylindrical_patch(s, n_arc, n_axial, "roof");
}

ShellMesh l_plate(const LPlate& s, int n_arm, int n_width) {
  const std::string who = "L-shaped plate";
  require_positive(who, "width", s.width);
  if (!s.origin.allFinite()) fail(who + ": the origin must be finite");
  const double w = s.width;
  // centre lines measured to the centre of the corner square: each arm is leg - w/2 long
  const double arm1_length = s.leg1 - w / 2, arm2_length = s.leg2 - w / 2;
  if (!(arm1_length > 0) || !(arm2_length > 0) || !std::isfinite(s.leg1) || !std::isfinite(s.leg2))
    fail(who + ": each leg (centre line to the corner centre: " + significant(s.leg1) + ", " + significant(s.leg2) +
         ") must be longer than half the width (" + significant(w / 2) + ")");
  const Vec3 o = s.origin;
  RectangularPlate arm1;
  arm1.a = arm1_length;
  arm1.b = w;
  arm1.origin = o;
  RectangularPlate corner;
  corner.a = w;
  corner.b = w;
  corner.origin = o + Vec3(arm1_length, 0, 0);
  RectangularPlate arm2;  // along +y; e_a x e_b = y x (-x) = +z keeps the normal
  arm2.a = arm2_length;
  arm2.b = w;
  arm2.origin = o + Vec3(arm1_length + w, w, 0);
  arm2.e_a = Vec3::UnitY();
  arm2.e_b = -Vec3::UnitX();
  ShellMesh p1 = rectangular_plate(arm1, n_arm, n_width, "arm1");
  ShellMesh pc = rectangular_plate(corner, n_width, n_width, "corner");
  ShellMesh p2 = rectangular_plate(arm2, n_arm, n_width, "arm2");
  p1.patches[0].edge_names = {"end", "corner", "outer", "inner"};
  pc.patches[0].edge_names = {"arm1", "outer2", "outer1", "arm2"};
  p2.patches[0].edge_names = {"corner", "end", "outer", "inner"};
  return assemble({p1, pc, p2});
}

ShellMesh l_plate_simo_fox_rifai(int n_arm, int n_width) {
  LPlate s;
  s.leg1 = s.leg2 = bench::kLPlateLeg;
  s.width = bench::kLPlateWidth;
  return l_plate(s, n_arm, n_width);
}

ShellMesh folded_plate(const FoldedPlate& s, int n_a, int n_b, int n_width) {
  const std::string who = "folded plate";
  if (!std::isfinite(s.fold_angle) || !(std::abs(s.fold_angle) < std::numbers::pi))
    fail(who + ": the fold angle must lie in (-180, 180) degrees (got " + significant(s.fold_angle * 180 / std::numbers::pi) +
         " deg); at 180 the legs would lie on each other");
  if (!s.origin.allFinite()) fail(who + ": the origin must be finite");
  // cos(pi/2) is 6e-17, not 0: snap round-off so a right-angle fold is exactly upright
  auto snapped = [](double v) { return std::abs(v) < 1e-15 ? 0.0 : v; };
  const Vec3 d(snapped(std::cos(s.fold_angle)), 0.0, snapped(std::sin(s.fold_angle)));
  RectangularPlate leg1;
  leg1.a = s.a;
  leg1.b = s.width;
  leg1.origin = s.origin;
  RectangularPlate leg2;  // e_a x e_b = d x y: the director turns continuously over the fold
  leg2.a = s.b;
  leg2.b = s.width;
  leg2.origin = s.origin + Vec3(s.a, 0, 0);
  leg2.e_a = d;
  leg2.e_b = Vec3::UnitY();
  ShellMesh p1 = rectangular_plate(leg1, n_a, n_width, "leg1");
  ShellMesh p2 = rectangular_plate(leg2, n_b, n_width, "leg2");
  p1.patches[0].edge_names = {"end", "fold", "y_min", "y_max"};
  p2.patches[0].edge_names = {"fold", "end", "y_min", "y_max"};
  return assemble({p1, p2});
}

long long patch_node_count(int nu, int nv, bool closed_u, bool closed_v) {
  return (static_cast<long long>(nu) + (closed_u ? 0 : 1)) * (static_cast<long long>(nv) + (closed_v ? 0 : 1));
}

long long polar_o_grid_node_count(int n_ring, int n_rim, int quadrants) {
  const int m = n_rim / (2 * quadrants);  // core elements per half-side, as polar_o_grid
  const int nx = quadrants >= 2 ? 2 * m : m, ny = quadrants == 4 ? 2 * m : m;
  const long long core = patch_node_count(nx, ny);
  // the ring's inner edge is the core's outline; over 360 degrees its seam is merged as well
  return quadrants == 4 ? core + static_cast<long long>(n_ring) * n_rim
                        : core + static_cast<long long>(n_ring) * (n_rim + 1);
}

long long l_plate_node_count(int n_arm, int n_width) {
  // arm1 | corner | arm2: the corner shares one edge of n_width + 1 nodes with each arm
  return 2 * patch_node_count(n_arm, n_width) + patch_node_count(n_width, n_width) - 2 * (n_width + 1LL);
}

long long folded_plate_node_count(int n_a, int n_b, int n_width) {
  return patch_node_count(n_a, n_width) + patch_node_count(n_b, n_width) - (n_width + 1LL);
}

ShellMesh right_angle_folded_plate(double a, double b, double width, int n_a, int n_b, int n_width) {
  FoldedPlate s;
  s.a = a;
  s.b = b;
  s.width = width;
  return folded_plate(s, n_a, n_b, n_width);
}

}  // namespace ff::mesh
