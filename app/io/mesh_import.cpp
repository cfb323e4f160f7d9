#include "app/io/mesh_import.h"

#include "app/io/abaqus_inp.h"
#include "app/io/gmsh_import.h"
#include "app/io/machine_memory.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "core/frame/input_file.h"
#include "core/mesh/generators.h"
#include "core/scene/mesh_file.h"

namespace ff::io {

namespace {

namespace fs = std::filesystem;
using ff::mesh::ShellMesh;
using Vec3 = Eigen::Vector3d;

// how to find the nodes and quads an error message names
constexpr const char* kNumbering = " (0-based numbers: quads in file order, nodes in order of first use by the quads)";

// corner normals of one node closer than this [rad] are one director; farther apart, a fold
constexpr double kFoldAngle = 1e-5;
// How far [deg] a file normal may tilt from its quad's own normal at that corner (the plane of
// the corner's two edges) beyond the turn of the file's normals across that quad: exact normals
// of a curved surface tilt from a flat quad by half the angle the element spans, which is half
// their turn across it, while normals tilted off a flat surface do not turn at all. A director
// off the surface shears the shell: a clamped plate's deflection grew 0.25 % at 3 deg, 2.8 % at
// 10, 11 % at 20 and 5000 times at 30, silently.
constexpr double kLargestDirectorTiltBeyondTurn = 5.0;
// and never more than this, whatever the turn: a director this far off is no shell's
constexpr double kLargestDirectorTilt = 60.0;
// A named group whose touching element edges are longer than this many times its part.local_sizes
// is said loudly: its local size did not reach the mesh
constexpr double kLocalSizeReachedWithin = 1.5;

std::string g_text(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// What the file says, before any joining: vertices with the file's own identity, quads by
// vertex index, the file normal at every quad corner (when the file has normals) and where each
// face was written (OBJ: its line; otherwise 0 and faces are named by their index).
struct RawSurface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 4>> quads;
  std::vector<std::array<Vec3, 4>> corner_normals;  // empty: the file has no normals
  std::vector<int> quad_line;                        // per quad; 0 where unknown
  std::vector<std::array<int, 3>> triangle_faces;    // kept for TriangleHandling::split
  std::vector<int> triangle_line;                    // per triangle; 0 where unknown
  int triangles = 0, polygons = 0, points_or_lines = 0, faces = 0;
  int first_other_line = 0, first_other_face = -1;   // where the first non-quad face is
  std::string format;                                // "OBJ", "PLY", ...
};

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string where(const RawSurface& raw, int q) {
  if (q < static_cast<int>(raw.quad_line.size()) && raw.quad_line[q] > 0) return "line " + std::to_string(raw.quad_line[q]);
  return "face " + std::to_string(q);
}

// ---- OBJ: read by its records, since assimp duplicates vertices per face corner ----------------
// assimp's OBJ importer copies every face corner into a vertex of its own, so which corners were
// one file vertex (and on which line a face was) is lost; a slit written with separate vertices
// could not be told from a seam. The records FlexFrame needs are few: v, vn, f (and l, p, which
// it refuses); everything else (vt, o, g, s, usemtl, mtllib) does not change the shell.

bool parse_double(std::string_view& s, double& x) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), x);
  if (r.ec == std::errc::result_out_of_range) {  // 1e999: report it as not finite below
    x = std::numeric_limits<double>::infinity();
  } else if (r.ec != std::errc()) {
    return false;
  }
  s.remove_prefix(static_cast<std::size_t>(r.ptr - s.data()));
  return s.empty() || s.front() == ' ' || s.front() == '\t';
}

bool read_obj(const std::string& path, const std::string& who, RawSurface& raw, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(error, "cannot open " + who);
  raw.format = "OBJ";
  std::vector<Vec3> normals;
  struct Face {
    int line;
    std::vector<long long> v, n;  // as written: 1-based, or negative = relative
  };
  std::vector<Face> faces;
  std::string line, logical;
  int line_no = 0, first_line = 0;
  const auto bad = [&](int at, const std::string& what) { return fail(error, who + " line " + std::to_string(at) + ": " + what); };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (logical.empty()) first_line = line_no;
    if (!line.empty() && line.back() == '\\') {  // continuation
      line.pop_back();
      logical += line + " ";
      continue;
    }
    logical += line;
    std::string_view s(logical);
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    const std::size_t sp = s.find_first_of(" \t");
    const std::string_view tag = s.substr(0, sp);
    std::string_view rest = sp == std::string_view::npos ? std::string_view{} : s.substr(sp);
    const int at = first_line;
    if (tag == "v" || tag == "vn") {
      Vec3 x;
      for (int k = 0; k < 3; ++k)
        if (!parse_double(rest, x[k]))
          return bad(at, std::string(tag == "v" ? "a vertex" : "a normal") + " needs three numbers ('" + logical + "')");
      if (!x.allFinite()) return bad(at, "the coordinates are not finite numbers ('" + logical + "')");
      if (x.cwiseAbs().maxCoeff() > 1e150)
        return bad(at, "a coordinate beyond 1e150 ('" + logical + "'); lengths must stay far from overflow");
      (tag == "v" ? raw.points : normals).push_back(x);
    } else if (tag == "f") {
      Face f{at, {}, {}};
      while (true) {
        while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
        if (rest.empty()) break;
        const std::size_t end = rest.find_first_of(" \t");
        const std::string_view token = rest.substr(0, end);
        rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end);
        // v, v/t, v//n, v/t/n
        long long idx[3] = {0, 0, 0};
        std::string_view t = token;
        for (int part = 0; part < 3 && !t.empty(); ++part) {
          const std::size_t slash = t.find('/');
          const std::string_view num = t.substr(0, slash);
          if (!num.empty()) {
            const auto r = std::from_chars(num.data(), num.data() + num.size(), idx[part]);
            if (r.ec != std::errc() || r.ptr != num.data() + num.size() || idx[part] == 0)
              return bad(at, "'" + std::string(token) + "' is not a vertex reference (1-based or negative indices)");
          }
          t = slash == std::string_view::npos ? std::string_view{} : t.substr(slash + 1);
        }
        if (idx[0] == 0) return bad(at, "'" + std::string(token) + "' names no vertex");
        // a negative index counts back from the last record read so far
        f.v.push_back(idx[0] < 0 ? static_cast<long long>(raw.points.size()) + idx[0] + 1 : idx[0]);
        f.n.push_back(idx[2] < 0 ? static_cast<long long>(normals.size()) + idx[2] + 1 : idx[2]);
      }
      if (f.v.empty()) return bad(at, "a face with no vertex indices (a shell face is 4 vertices: 'f a b c d')");
      ++raw.faces;
      if (f.v.size() == 4 || f.v.size() == 3) {
        faces.push_back(std::move(f));
        if (faces.back().v.size() == 3) {
          ++raw.triangles;
          if (!raw.first_other_line) raw.first_other_line = at;
        }
      } else {
        (f.v.size() == 3 ? raw.triangles : f.v.size() > 4 ? raw.polygons : raw.points_or_lines)++;
        if (!raw.first_other_line) raw.first_other_line = at;
      }
    } else if (tag == "l" || tag == "p") {
      ++raw.faces;
      ++raw.points_or_lines;
      if (!raw.first_other_line) raw.first_other_line = at;
    }
    logical.clear();
  }
  if (in.bad()) return fail(error, "reading " + who + " failed");

  const long long nv = static_cast<long long>(raw.points.size()), nn = static_cast<long long>(normals.size());
  bool all_normals = !faces.empty();
  for (const Face& f : faces)
    if (f.v.size() == 4)
      for (long long n : f.n) all_normals = all_normals && n != 0;
  for (const Face& f : faces) {
    for (long long v : f.v)
      if (v < 1 || v > nv)
        return bad(f.line, "vertex " + std::to_string(v) + " does not exist (the file has " + std::to_string(nv) + " vertices)");
    if (f.v.size() == 3) {
      raw.triangle_faces.push_back({static_cast<int>(f.v[0] - 1), static_cast<int>(f.v[1] - 1), static_cast<int>(f.v[2] - 1)});
      raw.triangle_line.push_back(f.line);
      continue;
    }
    std::array<int, 4> q;
    std::array<Vec3, 4> cn;
    for (int k = 0; k < 4; ++k) {
      q[k] = static_cast<int>(f.v[k] - 1);
      if (f.n[k] != 0 && (f.n[k] < 1 || f.n[k] > nn))
        return bad(f.line, "normal " + std::to_string(f.n[k]) + " does not exist (the file has " + std::to_string(nn) +
                               " normals)");
      if (all_normals) cn[k] = normals[static_cast<std::size_t>(f.n[k] - 1)];
    }
    raw.quads.push_back(q);
    raw.quad_line.push_back(f.line);
    if (all_normals) raw.corner_normals.push_back(cn);
  }
  return true;
}

// ---- other formats through assimp -----------------------------------------------------------

// ---- what a file declares, checked before it is read -----------------------------------------
// A PLY header states its element counts, and readers allocate for them before reading the body:
// a 600-byte file declaring 10^9 vertices took 11.7 GB in assimp. The counts are checked against
// what the file's bytes can hold and against the memory limit first.

// Peak bytes of an import per vertex and per face (assimp's scene and our copies; OBJ: our record
// reader; then the shell mesh, its orientation and validation): `check` of a 1000 x 1000 quad plate
// (1.0 M vertices, 1.0 M faces) peaked at 565 MB (OBJ) and 660 MB (PLY), about 50 MB of it the
// program's own; 250 + 400 bytes bound both
constexpr double kImportBytesPerVertex = 250.0, kImportBytesPerFace = 400.0;

double import_bytes(double vertices, double faces) {
  return vertices * kImportBytesPerVertex + faces * kImportBytesPerFace;
}

std::string gigabytes(double bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", bytes / 1e9);
  return b;
}

bool refuse_over_limit(const std::string& who, const std::string& what, double vertices, double faces,
                       double limit, std::string* error) {
  const double need = import_bytes(vertices, faces);
  if (!(limit > 0) || need <= limit) return true;
  char counts[96];
  std::snprintf(counts, sizeof counts, "%.0f vertices and %.0f faces", vertices, faces);
  return fail(error, who + ": " + what + " " + counts + "; reading them would need about " + gigabytes(need) +
                         " GB, more than the " + gigabytes(limit) + " GB this machine allows");
}

// bytes of one binary PLY scalar type; 0 for an unknown name
int ply_type_bytes(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// The PLY header's element counts against the body's size (each element takes at least: ASCII,
// two characters per property, a digit and a separator; binary, its scalars' bytes and each
// list's count) and against the memory limit. Also refuses a header that never ends (assimp's PLY
// reader loops at end of file then).
bool check_ply_header(const std::string& path, const std::string& who, double memory_limit, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  int n = 0;
  std::size_t bytes = 0;
  bool ascii = true;
  struct Element {
    std::string name;
    double count = 0;
    int line = 0;
    double min_bytes = 0;
  };
  std::vector<Element> elements;
  while (std::getline(in, line) && bytes < (1u << 20)) {
    bytes += line.size() + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (n++ == 0 && line != "ply") return fail(error, who + " line 1: a PLY file starts with 'ply'");
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string f;
      words >> f;
      ascii = f == "ascii";
    } else if (word == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      e.line = n;
      char* end = nullptr;
      e.count = std::strtod(count.c_str(), &end);
      if (count.empty() || *end != '\0' || !(e.count >= 0) || e.count != std::floor(e.count) || e.count > 9.2e18)
        return fail(error, who + " line " + std::to_string(n) + ": element '" + e.name + "' has no count of elements ('" +
                               count + "')");
      elements.push_back(e);
    } else if (word == "property" && !elements.empty()) {
      std::string type, count_type;
      words >> type;
      if (type == "list") words >> count_type;
      const int b = ply_type_bytes(type == "list" ? count_type : type);
      elements.back().min_bytes += ascii ? 2.0 : std::max(b, 1);
    } else if (word == "end_header") {
      std::error_code ec;
      const double file_bytes = static_cast<double>(fs::file_size(path, ec));
      const double body = ec ? 0.0 : file_bytes - static_cast<double>(bytes);
      double need = 0;
      for (const Element& e : elements) {
        need += e.count * e.min_bytes;
        // a binary file's last property may end without a separator: one byte of slack in ASCII
        if (need > body + 1) {
          char msg[160];
          std::snprintf(msg, sizeof msg, "the header declares %.0f '%s' elements, but the %.0f bytes after it hold at most %.0f",
                        e.count, e.name.c_str(), std::max(body, 0.0), std::floor((std::max(body, 0.0) + 1) / std::max(e.min_bytes, 1.0)));
          return fail(error, who + " line " + std::to_string(e.line) + ": " + msg + " (the header does not describe this file)");
        }
      }
      double vertices = 0, faces = 0;
      for (const Element& e : elements) (e.name == "vertex" ? vertices : e.name == "face" ? faces : vertices) += e.count;
      return refuse_over_limit(who, "its header declares", vertices, faces, memory_limit, error);
    }
  }
  return fail(error, who + ": the PLY header has no 'end_header' line (the file ends inside its header)");
}

// An OBJ is read record by record, so its memory follows its content: when its size could hold
// more records than the limit allows, count them (one pass, nothing kept) and refuse if they
// would not fit. The shortest vertex record is 8 bytes ("v 0 0 0\n"), the shortest quad 10.
bool check_obj_size(const std::string& path, const std::string& who, double memory_limit, std::string* error) {
  if (!(memory_limit > 0)) return true;
  std::error_code ec;
  const double bytes = static_cast<double>(fs::file_size(path, ec));
  if (ec || (import_bytes(bytes / 8.0, 0) <= memory_limit && import_bytes(0, bytes / 10.0) <= memory_limit)) return true;
  std::ifstream in(path, std::ios::binary);
  double vertices = 0, faces = 0;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t at = line.find_first_not_of(" \t");
    if (at == std::string::npos || at + 1 >= line.size() || (line[at + 1] != ' ' && line[at + 1] != '\t' && line[at + 1] != 'n'))
      continue;
    if (line[at] == 'v') vertices += 1;  // v and vn
    else if (line[at] == 'f') faces += 1;
  }
  return refuse_over_limit(who, "it holds", vertices, faces, memory_limit, error);
}

void add_mesh(const aiMesh& m, const aiMatrix4x4& X_WN, RawSurface& raw, bool& all_normals) {
  const int base = static_cast<int>(raw.points.size());
  for (unsigned v = 0; v < m.mNumVertices; ++v) {
    const aiVector3D p = X_WN * m.mVertices[v];
    raw.points.emplace_back(p.x, p.y, p.z);
  }
  aiMatrix3x3 N_WN(X_WN);  // normals turn with the node (rigid transforms in practice)
  all_normals = all_normals && m.HasNormals();
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    ++raw.faces;
    if (face.mNumIndices == 4) {
      std::array<int, 4> q;
      std::array<Vec3, 4> cn;
      for (int k = 0; k < 4; ++k) {
        q[k] = base + static_cast<int>(face.mIndices[k]);
        if (m.HasNormals()) {
          const aiVector3D n = N_WN * m.mNormals[face.mIndices[k]];
          cn[k] = Vec3(n.x, n.y, n.z);
        }
      }
      raw.quads.push_back(q);
      raw.corner_normals.push_back(cn);
      raw.quad_line.push_back(0);
    } else {
      (face.mNumIndices == 3 ? raw.triangles : face.mNumIndices > 4 ? raw.polygons : raw.points_or_lines)++;
      if (raw.first_other_face < 0) raw.first_other_face = raw.faces - 1;
      if (face.mNumIndices == 3) {
        raw.triangle_faces.push_back({base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                                      base + static_cast<int>(face.mIndices[2])});
        raw.triangle_line.push_back(0);
      }
    }
  }
}

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& X_WP, RawSurface& raw, bool& all_normals, int depth) {
  if (depth > 256) return;  // a cyclic or absurd node graph; validation refuses cycles anyway
  const aiMatrix4x4 X_WN = X_WP * node.mTransformation;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) add_mesh(*scene.mMeshes[node.mMeshes[k]], X_WN, raw, all_normals);
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], X_WN, raw, all_normals, depth + 1);
}

// the size bound of every file a mesh import reads (0: none known)
std::uintmax_t file_bound(double memory_limit) { return memory_limit > 0 ? static_cast<std::uintmax_t>(memory_limit) : 0; }

// An STL file must end as its format requires: assimp reads what it can of a damaged one and says
// nothing (an ASCII file cut inside facet 26 gave 26 triangles; one with random bytes inside facet 20, 20).
// Binary: an 80-byte header, the triangle count n, and exactly 50 n bytes after it (the test by
// which assimp tells binary from ASCII). ASCII: "solid name", then facets "facet normal x y z,
// outer loop, vertex x y z three times, endloop, endfacet", then "endsolid" (then another solid,
// or the end); nothing but text.
class AsciiStl {
 public:
  AsciiStl(const std::string& bytes, const std::string& who) : b_(bytes), who_(who) {}

  bool check(std::string* error) {
    if (!keyword("solid") || !skip_line()) return fail(error, problem_);
    while (true) {
      const std::string_view t = token();
      if (!problem_.empty()) return fail(error, problem_);
      if (t == "facet") {
        ++facet_;
        if (!facet()) return fail(error, problem_);
      } else if (t == "endsolid") {
        if (!skip_line()) return fail(error, problem_);
        ended_ = true;
        const std::string_view next = token();
        if (!problem_.empty()) return fail(error, problem_);
        if (next.empty()) return true;
        if (next != "solid" || !skip_line()) return fail(error, unexpected(next, "another 'solid' or the end of the file"));
        ended_ = false;
      } else {
        return fail(error, unexpected(t, "'facet' or 'endsolid'"));
      }
    }
  }

 private:
  static bool space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
  static bool text(char c) { return space(c) || (static_cast<unsigned char>(c) >= 0x20 && static_cast<unsigned char>(c) < 0x7f); }

  std::string place() const {
    return "line " + std::to_string(line_) +
           (inside_ ? ", inside facet " + std::to_string(facet_) : facet_ > 0 ? ", after facet " + std::to_string(facet_) : std::string());
  }
  bool not_text() {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned char>(b_[at_]));
    problem_ = who_ + " " + place() + ": a byte that is not text (" + hex + "); an ASCII STL holds only text (the "
               "file is damaged)";
    return false;
  }
  // the next whitespace-separated word; "" at the end of the file (or with problem_ set)
  std::string_view token() {
    for (; at_ < b_.size() && space(b_[at_]); ++at_)
      if (b_[at_] == '\n') ++line_;
    const std::size_t start = at_;
    for (; at_ < b_.size() && !space(b_[at_]); ++at_)
      if (!text(b_[at_])) return not_text(), std::string_view();
    return std::string_view(b_).substr(start, at_ - start);
  }
  // the rest of the line (a solid's name)
  bool skip_line() {
    for (; at_ < b_.size() && b_[at_] != '\n'; ++at_)
      if (!text(b_[at_])) return not_text();
    return true;
  }
  std::string unexpected(std::string_view found, const std::string& expected) {
    if (!problem_.empty()) return problem_;
    if (!ended_ && (found.empty() || at_ == b_.size())) {  // the end of the file, or a word the end cut
      const std::string cut = found.empty() ? "" : ", in the middle of '" + std::string(found.substr(0, 40)) + "'";
      return who_ + (inside_ ? " ends inside facet " + std::to_string(facet_) + " (line " + std::to_string(line_) + cut + ")"
                             : " ends after facet " + std::to_string(facet_) + cut) +
             " with no 'endsolid': the file was cut short";
    }
    return who_ + " " + place() + ": expected " + expected + ", found '" + std::string(found.substr(0, 40)) +
           "' (the file is damaged)";
  }
  bool keyword(const char* word) {
    const std::string_view t = token();
    if (t == word) return true;
    problem_ = unexpected(t, std::string("'") + word + "'");
    return false;
  }
  bool number() {
    const std::string_view t = token();
    double x = 0;
    std::string_view digits = !t.empty() && t.front() == '+' ? t.substr(1) : t;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), x);
    if (!t.empty() && (r.ec == std::errc() || r.ec == std::errc::result_out_of_range) && r.ptr == digits.data() + digits.size())
      return true;
    problem_ = unexpected(t, "a number");
    return false;
  }
  bool facet() {
    inside_ = true;
    if (!keyword("normal") || !number() || !number() || !number() || !keyword("outer") || !keyword("loop")) return false;
    for (int v = 0; v < 3; ++v)
      if (!keyword("vertex") || !number() || !number() || !number()) return false;
    if (!keyword("endloop") || !keyword("endfacet")) return false;
    inside_ = false;
    return true;
  }

  const std::string& b_;
  const std::string& who_;
  std::size_t at_ = 0;
  int line_ = 1, facet_ = 0;
  bool inside_ = false, ended_ = false;  // in a facet; after an endsolid
  std::string problem_;
};

bool check_stl_structure(const std::string& path, const std::string& who, double memory_limit, std::string* error) {
  std::string bytes, problem;
  const std::uintmax_t bound = file_bound(memory_limit);  // none known: the file's own size
  if (!read_input_file(path, &bytes, bound > 0 ? bound : std::numeric_limits<std::uintmax_t>::max(), kMemoryLimitBound,
                       &problem))
    return fail(error, who + " " + problem);
  const std::size_t size = bytes.size();
  std::uint32_t count = 0;
  if (size >= 84) std::memcpy(&count, bytes.data() + 80, 4);  // little-endian, as the format and this machine
  const std::uint64_t binary_size = 84 + 50 * static_cast<std::uint64_t>(count);
  if (size >= 84 && binary_size == size) return true;
  // ASCII when it starts "solid" and a facet or the end of the solid follows its first line
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  const std::size_t eol = bytes.find('\n');
  const std::size_t next = eol == std::string::npos ? std::string::npos : bytes.find_first_not_of(" \t\r\n", eol);
  const bool ascii = first != std::string::npos && bytes.compare(first, 5, "solid") == 0 && next != std::string::npos &&
                     (bytes.compare(next, 5, "facet") == 0 || bytes.compare(next, 8, "endsolid") == 0);
  if (ascii) return AsciiStl(bytes, who).check(error);
  if (size < 84)
    return fail(error, who + " is " + std::to_string(size) + " bytes: too short for a binary STL (an 80-byte header and a "
                             "4-byte triangle count), and not an ASCII STL (which begins 'solid', then 'facet')");
  return fail(error, who + " is not a complete binary STL: its header counts " + std::to_string(count) +
                         " triangles, which take 84 + 50 x " + std::to_string(count) + " = " +
                         std::to_string(binary_size) + " bytes, but the file has " + std::to_string(size) +
                         (size < binary_size ? " (cut short)" : " (other bytes follow them)") +
                         "; nor is it an ASCII STL (which begins 'solid', then 'facet')");
}

// Every file assimp opens (the mesh, and any it names: a glTF's buffers) passes the input-file
// check first: a regular file within the size bound. assimp's own Exists() opens the file, which
// blocks on a FIFO: here it only asks whether the name exists.
class CheckedFiles : public Assimp::DefaultIOSystem {
 public:
  explicit CheckedFiles(std::uintmax_t max_bytes) : max_bytes_(max_bytes) {}
  bool Exists(const char* file) const override {
    struct stat st {};
    return ::stat(file, &st) == 0;
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::strpbrk(mode, "wa+")) return nullptr;  // an importer writes nothing
    if (std::string p = input_file_problem(file, max_bytes_, kMemoryLimitBound); !p.empty()) {
      if (problem.empty()) problem = "'" + std::string(file) + "' " + p;
      return nullptr;
    }
    return DefaultIOSystem::Open(file, mode);
  }
  std::string problem;  ///< the first file refused

 private:
  std::uintmax_t max_bytes_;
};

bool read_with_assimp(const std::string& path, const std::string& who, RawSurface& raw, double memory_limit,
                      std::string* error) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply" && !check_ply_header(path, who, memory_limit, error)) return false;
  if (ext == ".stl" && !check_stl_structure(path, who, memory_limit, error)) return false;
  // ValidateDataStructure: indices in range, counts consistent, before anything reads them.
  // PLY keeps its vertices as written; formats that store a vertex per face corner (STL, glTF
  // and the rest) get identical corners joined, as their files carry no vertex identity.
  unsigned flags = aiProcess_ValidateDataStructure;
  if (ext != ".ply") flags |= aiProcess_JoinIdenticalVertices;
  Assimp::Importer importer;
  auto* files = new CheckedFiles(file_bound(memory_limit));
  importer.SetIOHandler(files);  // the importer owns it
  const aiScene* scene = importer.ReadFile(path, flags);
  if (!scene)
    return fail(error, "cannot read " + who + ": " + (files->problem.empty() ? importer.GetErrorString() : files->problem));
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) return fail(error, who + " was read only partially (incomplete scene)");
  raw.format = ext == ".ply" ? "PLY" : ext.empty() ? "mesh" : ext.substr(1);
  bool all_normals = true;
  if (scene->mRootNode) collect(*scene, *scene->mRootNode, aiMatrix4x4(), raw, all_normals, 0);
  else
    for (unsigned k = 0; k < scene->mNumMeshes; ++k) add_mesh(*scene->mMeshes[k], aiMatrix4x4(), raw, all_normals);
  if (!all_normals) raw.corner_normals.clear();
  for (std::size_t v = 0; v < raw.points.size(); ++v) {
    if (!raw.points[v].allFinite())
      return fail(error, who + ": vertex " + std::to_string(v) + " has coordinates that are not finite numbers");
    if (raw.points[v].cwiseAbs().maxCoeff() > 1e150)
      return fail(error, who + ": vertex " + std::to_string(v) + " has a coordinate beyond 1e150");
  }
  for (const auto& t : raw.triangle_faces)
    for (int k : t)
      if (k < 0 || k >= static_cast<int>(raw.points.size()))
        return fail(error, who + ": a triangle names vertex " + std::to_string(k) + ", which does not exist");
  for (std::size_t q = 0; q < raw.quads.size(); ++q)  // ValidateDataStructure checks this too; cheap to be sure
    for (int k : raw.quads[q])
      if (k < 0 || k >= static_cast<int>(raw.points.size()))
        return fail(error, who + ": " + where(raw, static_cast<int>(q)) + " names vertex " + std::to_string(k) +
                               ", which does not exist");
  return true;
}

// ---- from the file's surface to a shell mesh -------------------------------------------------

// drops vertices no quad uses and numbers the rest by first use in the face list
void renumber_by_first_use(RawSurface& raw) {
  std::vector<int> id(raw.points.size(), -1);
  std::vector<Vec3> points;
  for (auto& q : raw.quads)
    for (int& k : q) {
      if (id[k] < 0) {
        id[k] = static_cast<int>(points.size());
        points.push_back(raw.points[k]);
      }
      k = id[k];
    }
  raw.points = std::move(points);
}

// joins vertices closer than `tol` (first one kept), then renumbers by first use; refuses a
// tolerance that is not below half the shortest edge (it would collapse quads)
bool weld(RawSurface& raw, double tol, const std::string& who, std::string* error) {
  ShellMesh m;
  m.points = raw.points;
  m.normals.assign(raw.points.size(), Vec3::UnitZ());  // placeholders: assemble() needs a director
  m.quads = raw.quads;
  const double h = ff::mesh::min_edge_length(m);
  if (!(tol < 0.5 * h))
    return fail(error, who + ": the weld tolerance " + g_text(tol) + " is not below half the shortest edge (" +
                           g_text(h) + "); welding would collapse quads");
  ff::mesh::AssemblyOptions o;
  o.merge_tolerance = tol / h;
  const ShellMesh joined = ff::mesh::assemble({m}, o);
  raw.points = joined.points;
  raw.quads = joined.quads;
  renumber_by_first_use(raw);
  return true;
}

// directors from the file's normals: a node whose corner normals agree gets their mean; one whose
// corners differ (a crease the file draws) is a fold node with a director per corner
void directors_from_file(const RawSurface& raw, ShellMesh& m) {
  m.corner_normals.resize(m.quads.size());
  for (std::size_t q = 0; q < m.quads.size(); ++q)
    for (int k = 0; k < 4; ++k) m.corner_normals[q][k] = raw.corner_normals[q][k].normalized();
  std::vector<Vec3> first(m.points.size(), Vec3::Zero()), sum(m.points.size(), Vec3::Zero());
  m.fold.assign(m.points.size(), 0);
  for (std::size_t q = 0; q < m.quads.size(); ++q)
    for (int k = 0; k < 4; ++k) {
      const int I = m.quads[q][k];
      const Vec3& n = m.corner_normals[q][k];
      if (first[I].isZero()) first[I] = n;
      else if (std::acos(std::clamp(first[I].dot(n), -1.0, 1.0)) > kFoldAngle) m.fold[I] = 1;
      sum[I] += n;
    }
  m.normals.resize(m.points.size());
  for (std::size_t I = 0; I < m.points.size(); ++I) m.normals[I] = m.fold[I] ? first[I] : sum[I].normalized();
  for (std::size_t q = 0; q < m.quads.size(); ++q)
    for (int k = 0; k < 4; ++k)
      if (!m.fold[m.quads[q][k]]) m.corner_normals[q][k] = m.normals[m.quads[q][k]];
}

}  // namespace

bool import_shell_mesh(const std::string& path, ShellMesh& out, std::string* error, const MeshImportOptions& options,
                       bool* weld_tolerance_at_fault, std::vector<std::string>* warnings) {
  const std::string who = "mesh file '" + path + "'";
  if (weld_tolerance_at_fault) *weld_tolerance_at_fault = false;
  std::error_code ec;
  if (!fs::exists(path, ec)) return fail(error, who + " does not exist");
  if (fs::is_directory(path, ec)) return fail(error, who + " is a directory, not a mesh file");
  if (const std::string problem = input_file_problem(path, file_bound(options.memory_limit_bytes), kMemoryLimitBound);
      !problem.empty())
    return fail(error, who + " " + problem);
  if (!(options.weld_tolerance >= 0) || !std::isfinite(options.weld_tolerance)) {
    if (weld_tolerance_at_fault) *weld_tolerance_at_fault = true;
    return fail(error, "the weld tolerance must be a finite length >= 0");
  }

  RawSurface raw;
  const std::string ext = lower_extension(path);
  if (ext == ".obj" ? !check_obj_size(path, who, options.memory_limit_bytes, error) || !read_obj(path, who, raw, error)
                    : !read_with_assimp(path, who, raw, options.memory_limit_bytes, error))
    return false;

  if (raw.faces == 0) return fail(error, who + " contains no faces (a shell mesh needs quads)");
  const int not_quads = raw.faces - static_cast<int>(raw.quads.size());
  if (not_quads > 0 && not_quads == raw.triangles && options.triangles == ff::mesh::TriangleHandling::split) {
    // triangles (and quads): split into quads by core's conversion; the file's normals are not
    // used (the split makes new nodes the file has no normal for), directors are averaged
    if (options.weld_tolerance > 0) {
      if (weld_tolerance_at_fault) *weld_tolerance_at_fault = true;
      return fail(error, who + " holds triangles, and welding is done for quad meshes only: leave part.weld_tolerance "
                               "at 0 (STL vertices at one place are joined anyway)");
    }
    ff::mesh::ImportedSurface surface;
    surface.file = fs::path(path).filename().string();
    surface.format = raw.format;
    surface.points = raw.points;
    for (std::size_t q = 0; q < raw.quads.size(); ++q) {
      ff::mesh::ImportedElement e;
      e.nodes = raw.quads[q];
      e.where = where(raw, static_cast<int>(q));
      surface.elements.push_back(std::move(e));
    }
    for (std::size_t t = 0; t < raw.triangle_faces.size(); ++t) {
      ff::mesh::ImportedElement e;
      e.nodes = {raw.triangle_faces[t][0], raw.triangle_faces[t][1], raw.triangle_faces[t][2], -1};
      e.where = raw.triangle_line[t] > 0 ? "line " + std::to_string(raw.triangle_line[t]) : "triangle " + std::to_string(t);
      surface.elements.push_back(std::move(e));
    }
    ff::mesh::SurfaceConversionOptions convert;
    convert.triangles = ff::mesh::TriangleHandling::split;
    convert.crease_angle_deg = options.crease_angle_deg;
    convert.frame_reference = options.frame_reference;
    convert.patch_name = fs::path(path).stem().string();
    ff::mesh::SurfaceConversionReport report;
    ShellMesh m;
    if (!ff::mesh::shell_mesh_from_surface(surface, convert, m, error, &report)) return false;
    m.patches[0].description = "imported from " + surface.file + " (" + raw.format + "; " + report.summary() +
                               (raw.corner_normals.empty() ? "" : "; the file's normals are not used for a split mesh") + ")";
    if (warnings && !report.turned_warning().empty()) warnings->push_back("'" + surface.file + "': " + report.turned_warning());
    out = std::move(m);
    return true;
  }
  if (not_quads > 0) {
    std::string msg = who + ": " + std::to_string(not_quads) + " of " + std::to_string(raw.faces) +
                      " faces are not quads (" + std::to_string(raw.triangles) + " triangles, " +
                      std::to_string(raw.polygons) + " polygons with more than 4 vertices, " +
                      std::to_string(raw.points_or_lines) + " points or lines; the first " +
                      (raw.first_other_line ? "at line " + std::to_string(raw.first_other_line)
                                            : "is face " + std::to_string(raw.first_other_face)) +
                      "); shell elements are 4-node quads" +
                      (raw.triangles == not_quads ? std::string(": set part.triangles = \"split\" to split each triangle into three quads")
                                                  : std::string(", and only triangles can be split: export the surface with quads and triangles only"));
    if (ext == ".stl" || ext == ".gltf" || ext == ".glb")
      msg += " (STL and glTF 2.0 store triangles only: use OBJ or PLY for quad meshes)";
    return fail(error, msg);
  }
  const bool file_normals = !raw.corner_normals.empty();
  for (std::size_t q = 0; q < raw.corner_normals.size(); ++q)
    for (const Vec3& n : raw.corner_normals[q])
      if (!n.allFinite() || !(n.norm() > 1e-12))
        return fail(error, who + ": " + where(raw, static_cast<int>(q)) + " has a zero or non-finite normal");

  renumber_by_first_use(raw);
  if (options.weld_tolerance > 0 && !weld(raw, options.weld_tolerance, who, error)) {
    if (weld_tolerance_at_fault) *weld_tolerance_at_fault = true;
    return false;
  }

  ShellMesh m;
  m.points = std::move(raw.points);
  m.quads = raw.quads;
  if (file_normals) {
    // the file's normals say which side is the front: a quad wound against them is flipped only
    // when the scene allows it
    int against = 0, first_against = -1;
    for (int q = 0; q < m.quad_count(); ++q) {
      Vec3 n = Vec3::Zero();
      for (const Vec3& c : raw.corner_normals[q]) n += c.normalized();
      const Vec3 g = (m.points[m.quads[q][2]] - m.points[m.quads[q][0]]).cross(m.points[m.quads[q][3]] - m.points[m.quads[q][1]]);
      if (g.dot(n) < 0) {
        if (first_against < 0) first_against = q;
        ++against;
        std::swap(m.quads[q][1], m.quads[q][3]);
        std::swap(raw.corner_normals[q][1], raw.corner_normals[q][3]);
      }
    }
    if (against > 0 && !options.reorient)
      return fail(error, who + ": " + std::to_string(against) + " of " + std::to_string(m.quad_count()) +
                             " quads wind against the file's normals (the first at " + where(raw, first_against) +
                             "); fix the winding or the normals, or import with reorient");
  }
  {
    ShellMesh fixed = m;
    std::string why;
    if (!ff::mesh::orient_consistently(fixed, &why)) return fail(error, who + ": " + why + kNumbering);
    int flipped = 0;
    for (int q = 0; q < m.quad_count(); ++q) flipped += fixed.quads[q] != m.quads[q];
    if (flipped > 0 && (file_normals || !options.reorient))
      return fail(error, who + ": the faces are not consistently oriented (" + std::to_string(flipped) + " of " +
                             std::to_string(m.quad_count()) + " quads wind against their neighbours" +
                             (file_normals ? ", and the file's normals agree with each quad's own winding"
                                           : "; fix the winding or import with reorient") + ")");
    m.quads = std::move(fixed.quads);
  }
  std::string directors;
  if (file_normals) {
    // each file normal against its quad's own normal at that corner (the plane of its two
    // edges), and against the turn of the file's normals across the quad
    const auto angle = [](const Vec3& a, const Vec3& b) {
      return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi;
    };
    double largest_tilt = 0.0, largest_excess = -1.0, excess_tilt = 0.0, excess_turn = 0.0;
    int tilt_quad = -1, tilt_corner = 0, excess_quad = -1, excess_corner = 0;
    for (int q = 0; q < m.quad_count(); ++q) {
      const std::array<Vec3, 4>& n = raw.corner_normals[q];
      double turn = 0.0;
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) turn = std::max(turn, angle(n[a], n[b]));
      for (int k = 0; k < 4; ++k) {
        const Vec3& x = m.points[m.quads[q][k]];
        const Vec3 own = (m.points[m.quads[q][(k + 1) % 4]] - x).cross(m.points[m.quads[q][(k + 3) % 4]] - x);
        if (!(own.norm() > 0)) continue;  // a collapsed corner: validate() below names it
        const double tilt = angle(own, n[k]);
        if (tilt > largest_tilt) largest_tilt = tilt, tilt_quad = q, tilt_corner = k;
        const double excess = std::max(tilt - turn - kLargestDirectorTiltBeyondTurn, tilt - kLargestDirectorTilt);
        if (excess > largest_excess) largest_excess = excess, excess_tilt = tilt, excess_turn = turn, excess_quad = q, excess_corner = k;
      }
    }
    const auto place = [&](int q, int k) {
      const int node = m.quads[q][k];
      const Vec3& x = m.points[node];
      return where(raw, q) + ", corner " + std::to_string(k + 1) + " (node " + std::to_string(node) + " at [" +
             g_text(x.x()) + ", " + g_text(x.y()) + ", " + g_text(x.z()) + "])";
    };
    if (largest_excess > 0)
      return fail(error, who + ": the normal at " + place(excess_quad, excess_corner) + " is tilted " + g_text(excess_tilt) +
                             " deg from its quad's own normal, while the file's normals turn " + g_text(excess_turn) +
                             " deg across that quad; a director may tilt at most " +
                             g_text(kLargestDirectorTiltBeyondTurn) + " deg more than that turn (the tilt of exact "
                             "normals on a curved surface), and never more than " + g_text(kLargestDirectorTilt) +
                             " deg: a tilted director shears the shell and changes its stiffness. Fix the normals, "
                             "or leave them out of the file to have the directors averaged from the quads" + kNumbering);
    directors_from_file(raw, m);
    directors = "directors from the file's normals, at most " + g_text(largest_tilt) + " deg from the quads' own normals" +
                (tilt_quad >= 0 ? " (" + place(tilt_quad, tilt_corner) + ")" : std::string());
    if (m.fold_count() > 0)
      directors += " (" + std::to_string(m.fold_count()) + " crease nodes where they differ: 6 DoF there)";
  } else {
    ff::mesh::compute_area_weighted_normals(m);
    directors = "no normals in the file: directors averaged from the adjacent quads";
  }
  ff::mesh::compute_frames(m, options.frame_reference);
  m.patches.clear();
  ff::mesh::complete_layout(m, fs::path(path).stem().string());
  m.patches[0].description = "imported from " + fs::path(path).filename().string() + " (" + raw.format + ", " +
                             std::to_string(m.node_count()) + " nodes, " + std::to_string(m.quad_count()) + " quads" +
                             (options.weld_tolerance > 0 ? ", welded within " + std::to_string(options.weld_tolerance)
                                                         : ", vertices as written") +
                             "; " + directors + ")";

  const ff::mesh::MeshCheck check = ff::mesh::validate(m);
  if (!check.ok()) {
    std::string summary = check.summary();
    if (!summary.empty() && summary.back() == '\n') summary.pop_back();
    return fail(error, who + " is not a valid shell mesh" + kNumbering + ":\n" + summary);
  }
  out = std::move(m);
  return true;
}

namespace {
// progress of a long set-up on stderr: nothing for the first second (most set-ups take less),
// then a line at most every half second (rewritten in place on a terminal)
std::function<void(const std::string&, double)> setup_progress_printer() {
  struct State {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last{};
    bool printed = false;
  };
  auto state = std::make_shared<State>();
  const bool tty = isatty(STDERR_FILENO);
  return [state, tty](const std::string& phase, double fraction) {
    const auto now = std::chrono::steady_clock::now();
    if (now - state->start < std::chrono::seconds(1) || now - state->last < std::chrono::milliseconds(500)) return;
    state->last = now;
    state->printed = true;
    std::fprintf(stderr, "%sset-up: %s %3.0f%% (%.0f s)%s", tty ? "\r" : "", phase.c_str(), 100.0 * fraction,
                 std::chrono::duration<double>(now - state->start).count(), tty ? "\033[K" : "\n");
    std::fflush(stderr);
  };
}
}  // namespace

ff::scene::SceneContext scene_context(const std::atomic<bool>* stop) {
  ff::scene::SceneContext ctx;
  if (stop) {
    ctx.setup.stop = stop;
    ctx.setup.progress = setup_progress_printer();
  }
  ctx.memory_limit_bytes = machine_memory_limit_bytes();
  ctx.mesh_reader = [limit = ctx.memory_limit_bytes, stop](const ff::scene::MeshFileRequest& request, ShellMesh& out,
                                                           ff::scene::MeshFileError* error,
                                                           std::vector<std::string>* warnings) {
    // a scene's parts are read more than once (their size for the memory check, then the mesh,
    // and `check` loads twice): a file is read, and a CAD part meshed, once per process as long
    // as it is unchanged on disk (its size and modification time). A refusal is kept too (a part
    // stopped at part.mesh_time_limit took that limit at every read), except one by the stop flag.
    struct Cached {
      ff::scene::MeshFileRequest request;
      std::uintmax_t size;
      fs::file_time_type modified;
      ShellMesh mesh;
      std::vector<std::string> warnings;
      std::optional<ff::scene::MeshFileError> refusal;
    };
    static std::mutex mutex;
    static std::vector<Cached> cache;
    std::error_code ec1, ec2;
    const std::uintmax_t size = fs::file_size(request.path, ec1);
    const fs::file_time_type modified = fs::last_write_time(request.path, ec2);
    const bool cacheable = !ec1 && !ec2;
    if (cacheable) {
      std::lock_guard<std::mutex> lock(mutex);
      for (const Cached& c : cache)
        if (c.request == request && c.size == size && c.modified == modified) {
          if (c.refusal) {
            if (error) *error = *c.refusal;
            return false;
          }
          out = c.mesh;
          if (warnings) *warnings = c.warnings;
          return true;
        }
    }
    ff::scene::MeshFileError local;
    ff::scene::MeshFileError& e = error ? *error : local;
    std::vector<std::string> said;
    const bool ok = read_mesh_file(request, out, e, limit, stop, &said);
    if (cacheable && !(stop && stop->load())) {
      std::lock_guard<std::mutex> lock(mutex);
      if (cache.size() >= 4) cache.erase(cache.begin());  // a study's variants: a few meshes at a time
      cache.push_back({request, size, modified, ok ? out : ShellMesh(), said, ok ? std::nullopt : std::optional(e)});
    }
    if (ok && warnings) *warnings = std::move(said);
    return ok;
  };
  return ctx;
}

bool read_mesh_file(const ff::scene::MeshFileRequest& request, ShellMesh& out, ff::scene::MeshFileError& error,
                    double memory_limit_bytes, const std::atomic<bool>* stop, std::vector<std::string>* warnings) {
  const std::string ext = lower_extension(request.path);
  const std::string name = fs::path(request.path).filename().string();
  const bool gmsh = gmsh_reads(request.path), geometry = gmsh_is_geometry(request.path);
  const bool by_gmsh = gmsh;
  const auto refuse = [&](const std::string& key, const std::string& message) {
    error.key = key;
    error.message = message;
    return false;
  };
  // keys that only some formats use: refused where they would do nothing
  if (!geometry && request.mesh_size > 0)
    return refuse("part.mesh_size", "part.mesh_size is the element size Gmsh meshes a CAD part at (STEP, IGES, BREP, "
                                    ".geo); '" + name + "' is a mesh already");
  if (!geometry && !request.local_size_groups.empty())
    return refuse("part.local_size_groups", "part.local_size_groups sizes the mesh Gmsh makes of a CAD part; '" + name +
                                                "' is a mesh already");
  if (geometry && ext != ".geo" && !(request.mesh_size > 0))
    return refuse("part.mesh_size", "'" + name + "' is a CAD part: Gmsh meshes it at the size part.mesh_size, which "
                                    "the scene must give, greater than 0 (the largest element edge, in the scene's "
                                    "length unit)");
  if (request.triangles == "recombine" && !by_gmsh)
    return refuse("part.triangles", "Gmsh recombines the triangles of .msh files (on an STL it broke the surface: "
                                    "Gmsh 4.8 found no boundary to match against); '" + name +
                                        "' is read otherwise: use part.triangles = \"split\"");
  if (!request.group.empty() && !by_gmsh && ext != ".inp")
    return refuse("part.group", "'" + name + "' has no named groups (they come from Gmsh .msh and CAD files, and "
                                "Abaqus .inp sets): part.group cannot pick one");
  if (request.weld_tolerance > 0 && (by_gmsh || ext == ".inp"))
    return refuse("part.weld_tolerance", "part.weld_tolerance joins the loose vertices of OBJ and PLY files; '" + name +
                                             "' numbers its nodes, and elements that share a node share it already");

  ShellMesh m;
  std::vector<std::string> said;
  if (ext == ".inp" || by_gmsh) {
    ff::mesh::ImportedSurface surface;
    if (ext == ".inp") {
      std::string why;
      if (!read_abaqus_inp(request.path, surface, &why, memory_limit_bytes)) return refuse("part.file", why);
      surface.file = name;
    } else {
      GmshMeshRequest g;
      g.path = request.path;
      g.mesh_geometry = geometry;
      g.mesh_size = request.mesh_size;
      for (std::size_t k = 0; k < request.local_size_groups.size() && k < request.local_sizes.size(); ++k)
        g.group_sizes.emplace_back(request.local_size_groups[k], request.local_sizes[k]);
      g.recombine_triangles = request.triangles == "recombine";
      g.join_touching_faces = !request.keep_faces_apart;
      g.mapped_faces = request.mesh_pattern == "mapped";
      g.time_limit_seconds = request.time_limit_seconds;
      g.memory_limit_bytes = memory_limit_bytes;
      g.most_nodes = request.most_nodes;
      g.stop = stop;
      std::string why;
      if (!read_with_gmsh(g, surface, &why)) {
        // a group size naming no group, a size the script's bounds refuse, or a mesh size too fine
        // for the memory, is the scene's key
        return refuse(why.find("part.local_sizes") != std::string::npos         ? "part.local_sizes"
                      : why.find("part.local_size_groups") != std::string::npos ? "part.local_size_groups"
                      : why.find("raise part.mesh_size") != std::string::npos && request.mesh_size > 0 ? "part.mesh_size"
                                                                                 : "part.file",
                      why);
      }
    }
    ff::mesh::SurfaceConversionOptions convert;
    convert.triangles = request.triangles == "refuse" ? ff::mesh::TriangleHandling::refuse : ff::mesh::TriangleHandling::split;
    convert.crease_angle_deg = request.crease_angle_deg;
    convert.patch_name = request.group.empty() ? fs::path(request.path).stem().string() : request.group;
    convert.only_group = request.group;
    ff::mesh::SurfaceConversionReport report;
    std::string why;
    if (!ff::mesh::shell_mesh_from_surface(surface, convert, m, &why, &report)) {
      const bool group_at_fault = !request.group.empty() && why.find("no surface group called") != std::string::npos;
      const bool triangles_at_fault = why.find("part.triangles") != std::string::npos;
      return refuse(group_at_fault ? "part.group" : triangles_at_fault ? "part.triangles" : "part.file",
                    "mesh file '" + request.path + "': " + why);
    }
    if (!report.turned_warning().empty()) said.push_back("'" + name + "': " + report.turned_warning());
    std::string notes;
    for (const std::string& n : surface.notes) notes += "; " + n;
    // what the mesh reached, measured on it: the mean element edge, and at each group given a
    // local size the edges that touch it (the script's own settings or a field may win there)
    if (geometry) {
      notes += "; element edges " + g_text(ff::mesh::mean_edge_length(m)) + " long on average";
      for (std::size_t k = 0; k < request.local_size_groups.size() && k < request.local_sizes.size(); ++k) {
        const int at = m.find_group(request.local_size_groups[k]);
        if (at < 0) continue;  // a group of another part cut from the same file
        int edges = 0;
        const double reached = ff::mesh::mean_edge_length(m, &m.groups[static_cast<std::size_t>(at)], &edges);
        const std::string& group = request.local_size_groups[k];
        const double asked = request.local_sizes[k];
        notes += "; at '" + group + "' " + g_text(reached) + " (asked " + g_text(asked) + "; the mean of the " +
                 std::to_string(edges) + " element edges that touch it)";
        if (reached > kLocalSizeReachedWithin * asked)
          said.push_back("'" + name + "': the element edges that touch group '" + group + "' are " + g_text(reached) +
                         " long on average, not the " + g_text(asked) + " part.local_sizes asks: the file's own "
                         "settings (a transfinite curve, a field) or the group's geometry set the size there");
      }
    }
    std::string groups;
    for (const ff::mesh::MeshGroup& grp : m.groups) groups += (groups.empty() ? "" : ", ") + grp.name;
    m.patches[0].description = "imported from " + surface.file + " (" + surface.format + notes + "; " + report.summary() +
                               "; " + std::to_string(m.node_count()) + " nodes" +
                               (groups.empty() ? std::string("; no named groups") : "; named groups: " + groups) + ")";
  } else {
    MeshImportOptions options;
    options.weld_tolerance = request.weld_tolerance;
    options.memory_limit_bytes = memory_limit_bytes;
    options.triangles = request.triangles == "refuse" ? ff::mesh::TriangleHandling::refuse : ff::mesh::TriangleHandling::split;
    options.crease_angle_deg = request.crease_angle_deg;
    bool tolerance_at_fault = false;
    if (!import_shell_mesh(request.path, m, &error.message, options, &tolerance_at_fault, &said)) {
      if (tolerance_at_fault) error.key = "part.weld_tolerance";
      return false;
    }
  }
  // faces that touch without sharing their nodes compute as pieces apart: refused unless the scene
  // says they are meant to be (a slit, a lap that is not bonded)
  const ff::mesh::UnjoinedContacts contacts = ff::mesh::find_unjoined_contacts(m);
  if (contacts.nodes > 0) {
    const Eigen::Vector3d& x = m.points[static_cast<std::size_t>(contacts.first_node)];
    const std::string where = std::to_string(contacts.nodes) + " boundary nodes lie on elements they are not joined "
                              "to (the first at [" + g_text(x.x()) + ", " + g_text(x.y()) + ", " + g_text(x.z()) + "])";
    if (!request.keep_faces_apart)
      return refuse("part.file",
                    "mesh file '" + request.path + "': its faces touch without being joined: " + where +
                        ", so the shell would come apart there (faces side by side, each with its own row of nodes; a "
                        "stiffener whose foot does not share the nodes of the face it stands on). " +
                        (ext == ".geo" ? "FlexFrame joins the touching faces of OpenCASCADE geometry, not those of "
                                         "Gmsh's built-in kernel: join them in the script (Coherence for faces side by side, "
                                         "Curve{...} In Surface{...} for a foot on a face), or build it with "
                                         "SetFactory(\"OpenCASCADE\")"
                         : geometry ? "FlexFrame joined the touching CAD faces it found, and these still touch: check "
                                      "the CAD model"
                         : by_gmsh || ext == ".inp"
                             ? "Join them in the file (in Gmsh, before meshing: BooleanFragments of OpenCASCADE "
                               "geometry, Coherence of the built-in kernel's)"
                             : "Give part.weld_tolerance to join vertices at one place, or join them in the file") +
                        "; or set part.keep_faces_apart = true if they are meant to be apart (a slit, a lap that is not "
                        "bonded)");
    m.patches[0].description.insert(m.patches[0].description.size() - 1,
                                    "; faces kept apart where they touch (part.keep_faces_apart): " + where);
  }
  out = std::move(m);
  if (warnings) *warnings = std::move(said);
  return true;
}

bool write_shell_mesh_obj(const std::string& path, const ShellMesh& mesh, std::string* error, bool normals) {
  std::ofstream f(path);
  if (!f) return fail(error, "cannot open '" + path + "' for writing");
  f.precision(17);
  f << "# FlexFrame shell mesh: " << mesh.node_count() << " nodes, " << mesh.quad_count() << " quads\n";
  for (const auto& p : mesh.points) f << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  if (normals) {
    // one normal per quad corner (fold nodes carry a director per corner)
    for (const auto& c : mesh.corner_normals)
      for (const auto& n : c) f << "vn " << n.x() << " " << n.y() << " " << n.z() << "\n";
    for (int q = 0; q < mesh.quad_count(); ++q) {
      f << "f";
      for (int k = 0; k < 4; ++k) f << " " << mesh.quads[q][k] + 1 << "//" << 4 * q + k + 1;
      f << "\n";
    }
  } else {
    for (const auto& q : mesh.quads) f << "f " << q[0] + 1 << " " << q[1] + 1 << " " << q[2] + 1 << " " << q[3] + 1 << "\n";
  }
  if (!f) return fail(error, "writing '" + path + "' failed");
  return true;
}

bool write_shell_mesh_ply(const std::string& path, const ShellMesh& mesh, std::string* error, bool normals) {
  std::ofstream f(path);
  if (!f) return fail(error, "cannot open '" + path + "' for writing");
  f.precision(17);
  f << "ply\nformat ascii 1.0\ncomment FlexFrame shell mesh\nelement vertex " << mesh.node_count()
    << "\nproperty double x\nproperty double y\nproperty double z\n"
    << (normals ? "property double nx\nproperty double ny\nproperty double nz\n" : "") << "element face " << mesh.quad_count()
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < mesh.node_count(); ++i) {
    const auto& p = mesh.points[i];
    f << p.x() << " " << p.y() << " " << p.z();
    if (normals) f << " " << mesh.normals[i].x() << " " << mesh.normals[i].y() << " " << mesh.normals[i].z();
    f << "\n";
  }
  for (const auto& q : mesh.quads) f << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  if (!f) return fail(error, "writing '" + path + "' failed");
  return true;
}

}  // namespace ff::io
