#include "app/io/gmsh_import.h"

#include "app/io/machine_memory.h"
#include "core/frame/input_file.h"
#include "core/frame/text.h"

// Gmsh's C API, for its function types only: the library is opened with dlopen in the child
// process, so `flexframe` neither links it nor loads it (with OpenCASCADE, 91 libraries, 84 ms and
// 50 MB at every start-up) unless a scene reads a Gmsh file
#include <gmshc.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <link.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/landlock.h>
#include <linux/seccomp.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace ff::io {

namespace {

namespace fs = std::filesystem;
using ff::mesh::ImportedElement;
using ff::mesh::ImportedGroup;
using ff::mesh::ImportedSurface;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// ---- the byte stream between the child and the parent ------------------------------------------

struct Writer {
  std::string bytes;
  template <class T>
  void put(const T& v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes += s;
  }
  template <class T>
  void put_array(const std::vector<T>& v) {
    put<std::uint64_t>(v.size());
    if (!v.empty()) bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
};

struct Reader {
  const std::string& bytes;
  std::size_t at = 0;
  bool ok = true;
  template <class T>
  T get() {
    T v{};
    if (!ok || bytes.size() - at < sizeof(T)) return ok = false, v;
    std::memcpy(&v, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
  std::string get_string() {
    const std::uint64_t n = get<std::uint64_t>();
    if (!ok || bytes.size() - at < n) return ok = false, std::string();
    std::string s = bytes.substr(at, n);
    at += n;
    return s;
  }
  template <class T>
  std::vector<T> get_array() {
    const std::uint64_t n = get<std::uint64_t>();
    if (!ok || (bytes.size() - at) / sizeof(T) < n) return ok = false, std::vector<T>();
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));  // an empty vector's data() may be null
    at += n * sizeof(T);
    return v;
  }
};

// ---- the child: Gmsh through its C API ----------------------------------------------------------

// Gmsh's C functions, looked up by name in libgmsh
struct GmshApi {
  decltype(&::gmshInitialize) initialize = nullptr;
  decltype(&::gmshOpen) open = nullptr;
  decltype(&::gmshOptionSetNumber) set_number = nullptr;
  decltype(&::gmshModelGetEntities) get_entities = nullptr;
  decltype(&::gmshModelGetPhysicalGroups) get_physical_groups = nullptr;
  decltype(&::gmshModelGetEntitiesForPhysicalGroup) get_entities_for_physical_group = nullptr;
  decltype(&::gmshModelGetPhysicalName) get_physical_name = nullptr;
  decltype(&::gmshModelGetBoundary) get_boundary = nullptr;
  decltype(&::gmshModelGetType) get_type = nullptr;
  decltype(&::gmshModelGetNormal) get_normal = nullptr;
  decltype(&::gmshModelGetParametrization) get_parametrization = nullptr;
  decltype(&::gmshModelMeshGenerate) generate = nullptr;
  decltype(&::gmshModelMeshRecombine) recombine = nullptr;
  decltype(&::gmshModelMeshClear) clear = nullptr;
  decltype(&::gmshModelMeshGetNodes) get_nodes = nullptr;
  decltype(&::gmshModelMeshGetNodesForPhysicalGroup) get_nodes_for_physical_group = nullptr;
  decltype(&::gmshModelMeshGetElements) get_elements = nullptr;
  decltype(&::gmshModelMeshSetSize) set_size = nullptr;
  decltype(&::gmshModelMeshSetTransfiniteCurve) set_transfinite_curve = nullptr;
  decltype(&::gmshModelMeshSetTransfiniteSurface) set_transfinite_surface = nullptr;
  decltype(&::gmshModelMeshSetRecombine) set_recombine = nullptr;
  decltype(&::gmshModelMeshGetEmbedded) get_embedded = nullptr;
  decltype(&::gmshModelOccGetMass) occ_get_mass = nullptr;
  decltype(&::gmshLoggerStart) logger_start = nullptr;
  decltype(&::gmshLoggerGetLastError) last_error = nullptr;
  decltype(&::gmshLoggerGet) logger_get = nullptr;
  decltype(&::gmshOptionGetNumber) get_number = nullptr;
  decltype(&::gmshModelGetBoundingBox) get_bounding_box = nullptr;
  decltype(&::gmshModelGetEntitiesInBoundingBox) get_entities_in_bounding_box = nullptr;
  decltype(&::gmshModelGetValue) get_value = nullptr;
  decltype(&::gmshModelGetParametrizationBounds) get_parametrization_bounds = nullptr;
  decltype(&::gmshModelGetClosestPoint) get_closest_point = nullptr;
  decltype(&::gmshModelAddPhysicalGroup) add_physical_group = nullptr;
  decltype(&::gmshModelSetPhysicalName) set_physical_name = nullptr;
  decltype(&::gmshModelRemovePhysicalGroups) remove_physical_groups = nullptr;
  decltype(&::gmshModelOccGetEntities) occ_get_entities = nullptr;
  decltype(&::gmshModelOccFragment) occ_fragment = nullptr;
  decltype(&::gmshModelOccCopy) occ_copy = nullptr;
  decltype(&::gmshModelOccRemove) occ_remove = nullptr;
  decltype(&::gmshModelOccSynchronize) occ_synchronize = nullptr;

  std::string load() {
    void* h = nullptr;
    for (const char* name : {"libgmsh.so", "libgmsh.so.4.8"})
      if ((h = dlopen(name, RTLD_NOW | RTLD_LOCAL))) break;
    if (!h)
      return std::string("the Gmsh library is not installed (Debian: apt-get install libgmsh-dev; scripts/setup does "
                         "it): ") + dlerror();
    std::string missing;
    const auto find = [&](auto& fn, const char* symbol) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(h, symbol));
      if (!fn) missing += std::string(missing.empty() ? "" : ", ") + symbol;
    };
    find(initialize, "gmshInitialize");
    find(open, "gmshOpen");
    find(set_number, "gmshOptionSetNumber");
    find(get_entities, "gmshModelGetEntities");
    find(get_physical_groups, "gmshModelGetPhysicalGroups");
    find(get_entities_for_physical_group, "gmshModelGetEntitiesForPhysicalGroup");
    find(get_physical_name, "gmshModelGetPhysicalName");
    find(get_boundary, "gmshModelGetBoundary");
    find(get_type, "gmshModelGetType");
    find(get_normal, "gmshModelGetNormal");
    find(get_parametrization, "gmshModelGetParametrization");
    find(generate, "gmshModelMeshGenerate");
    find(recombine, "gmshModelMeshRecombine");
    find(clear, "gmshModelMeshClear");
    find(get_nodes, "gmshModelMeshGetNodes");
    find(get_nodes_for_physical_group, "gmshModelMeshGetNodesForPhysicalGroup");
    find(get_elements, "gmshModelMeshGetElements");
    find(set_size, "gmshModelMeshSetSize");
    find(set_transfinite_curve, "gmshModelMeshSetTransfiniteCurve");
    find(set_transfinite_surface, "gmshModelMeshSetTransfiniteSurface");
    find(set_recombine, "gmshModelMeshSetRecombine");
    find(get_embedded, "gmshModelMeshGetEmbedded");
    find(occ_get_mass, "gmshModelOccGetMass");
    find(logger_start, "gmshLoggerStart");
    find(last_error, "gmshLoggerGetLastError");
    find(logger_get, "gmshLoggerGet");
    find(get_number, "gmshOptionGetNumber");
    find(get_bounding_box, "gmshModelGetBoundingBox");
    find(get_entities_in_bounding_box, "gmshModelGetEntitiesInBoundingBox");
    find(get_value, "gmshModelGetValue");
    find(get_parametrization_bounds, "gmshModelGetParametrizationBounds");
    find(get_closest_point, "gmshModelGetClosestPoint");
    find(add_physical_group, "gmshModelAddPhysicalGroup");
    find(set_physical_name, "gmshModelSetPhysicalName");
    find(remove_physical_groups, "gmshModelRemovePhysicalGroups");
    find(occ_get_entities, "gmshModelOccGetEntities");
    find(occ_fragment, "gmshModelOccFragment");
    find(occ_copy, "gmshModelOccCopy");
    find(occ_remove, "gmshModelOccRemove");
    find(occ_synchronize, "gmshModelOccSynchronize");
    return missing.empty() ? std::string() : "the Gmsh library lacks " + missing + " (Gmsh 4.8 or later is needed)";
  }

  // the first line Gmsh logged as an error, or ""
  std::string first_logged_error() const {
    char** log = nullptr;
    std::size_t n = 0;
    int ierr = 0;
    logger_get(&log, &n, &ierr);
    for (std::size_t k = 0; k < n; ++k)
      if (log[k] && std::strncmp(log[k], "Error", 5) == 0) return log[k];
    return {};
  }

  // the last error Gmsh logged (its API returns a non-zero ierr and logs why)
  std::string why() const {
    char* e = nullptr;
    int ierr = 0;
    last_error(&e, &ierr);
    std::string s = e ? e : "";
    if (s.empty()) {  // some failures log only ordinary messages: take the last error-like line
      char** log = nullptr;
      std::size_t n = 0;
      logger_get(&log, &n, &ierr);
      for (std::size_t k = n; k-- > 0;)
        if (log[k] && std::strstr(log[k], "rror")) {
          s = log[k];
          break;
        }
    }
    return s.empty() ? std::string("Gmsh gave no reason") : s;
  }
};

struct GmshFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void check(const GmshApi& g, int ierr, const std::string& doing) {
  if (ierr != 0) throw GmshFailure(doing + ": " + g.why());
}

// Refuse every call that writes, creates, deletes, renames, executes or opens a socket: a .geo
// script runs with what the file system offers to read, nothing more. Returns false when the
// kernel refuses the filter (the caller then refuses scripts).
bool enter_read_only_sandbox() {
#if defined(__x86_64__)
  constexpr std::uint32_t arch = AUDIT_ARCH_X86_64;
#elif defined(__aarch64__)
  constexpr std::uint32_t arch = AUDIT_ARCH_AARCH64;
#else
  return false;
#endif
#if defined(__x86_64__) || defined(__aarch64__)
  const long denied[] = {
      SYS_execve, SYS_execveat, SYS_unlinkat, SYS_renameat2, SYS_mkdirat, SYS_linkat, SYS_symlinkat, SYS_truncate,
      SYS_fchmodat, SYS_fchownat, SYS_mknodat, SYS_socket, SYS_connect, SYS_ptrace, SYS_kill, SYS_openat2,
#if defined(__x86_64__)
      SYS_unlink, SYS_rename, SYS_renameat, SYS_mkdir, SYS_rmdir, SYS_link, SYS_symlink, SYS_chmod, SYS_chown,
      SYS_lchown, SYS_mknod, SYS_creat,
#endif
  };
  constexpr std::uint32_t write_flags = O_WRONLY | O_RDWR | O_CREAT | O_TRUNC | O_APPEND;
  std::vector<sock_filter> f;
  const auto stmt = [&](std::uint16_t code, std::uint32_t k) { f.push_back(BPF_STMT(code, k)); };
  const auto jump = [&](std::uint16_t code, std::uint32_t k, std::uint8_t jt, std::uint8_t jf) {
    f.push_back(BPF_JUMP(code, k, jt, jf));
  };
  const std::uint32_t refuse = SECCOMP_RET_ERRNO | (EPERM & SECCOMP_RET_DATA);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, arch));
  jump(BPF_JMP | BPF_JEQ | BPF_K, arch, 1, 0);
  stmt(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, nr));
  for (long nr : denied) {
    jump(BPF_JMP | BPF_JEQ | BPF_K, static_cast<std::uint32_t>(nr), 0, 1);
    stmt(BPF_RET | BPF_K, refuse);
  }
  // open/openat with any flag that writes: refused (read-only opens pass)
#if defined(__x86_64__)
  jump(BPF_JMP | BPF_JEQ | BPF_K, SYS_open, 0, 4);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, args[1]));
  jump(BPF_JMP | BPF_JSET | BPF_K, write_flags, 0, 1);
  stmt(BPF_RET | BPF_K, refuse);
  stmt(BPF_RET | BPF_K, SECCOMP_RET_ALLOW);
#endif
  jump(BPF_JMP | BPF_JEQ | BPF_K, SYS_openat, 0, 4);
  stmt(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, args[2]));
  jump(BPF_JMP | BPF_JSET | BPF_K, write_flags, 0, 1);
  stmt(BPF_RET | BPF_K, refuse);
  stmt(BPF_RET | BPF_K, SECCOMP_RET_ALLOW);
  stmt(BPF_RET | BPF_K, SECCOMP_RET_ALLOW);  // every other call
  sock_fprog prog{static_cast<unsigned short>(f.size()), f.data()};
  if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) return false;
  return prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &prog) == 0;
#endif
}

// Reads confined to the folders in `readable` and below (Landlock, Linux 5.13 or later): a .geo
// script may Include or Merge the files beside its own and below, and read nothing else: not
// /etc, not the user's home, not /proc/<the parent>/environ (the environment is cleared in the
// child, but /proc keeps every process's first one). Returns "" when confined, else why not.
std::string confine_reads(const std::vector<std::string>& readable) {
  const long abi = syscall(SYS_landlock_create_ruleset, nullptr, 0, LANDLOCK_CREATE_RULESET_VERSION);
  if (abi < 1) return "this kernel offers no Landlock (Linux 5.13 or later, with Landlock enabled)";
  landlock_ruleset_attr attr{};
  attr.handled_access_fs = (LANDLOCK_ACCESS_FS_MAKE_SYM << 1) - 1;  // every file-system right of its first version
  const int ruleset = static_cast<int>(syscall(SYS_landlock_create_ruleset, &attr, sizeof attr, 0));
  if (ruleset < 0) return std::string("the kernel refused a Landlock rule set: ") + std::strerror(errno);
  std::string problem;
  for (const std::string& dir : readable) {
    landlock_path_beneath_attr rule{};
    rule.allowed_access = LANDLOCK_ACCESS_FS_READ_FILE | LANDLOCK_ACCESS_FS_READ_DIR;
    rule.parent_fd = ::open(dir.c_str(), O_PATH | O_CLOEXEC);
    if (rule.parent_fd < 0) continue;  // a folder that is not there needs no rule
    if (syscall(SYS_landlock_add_rule, ruleset, LANDLOCK_RULE_PATH_BENEATH, &rule, 0) != 0 && problem.empty())
      problem = "the kernel refused the Landlock rule for " + dir + ": " + std::strerror(errno);
    close(rule.parent_fd);
  }
  if (problem.empty() && (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 || syscall(SYS_landlock_restrict_self, ruleset, 0) != 0))
    problem = std::string("the kernel refused to apply Landlock's rules: ") + std::strerror(errno);
  close(ruleset);
  return problem;
}

// the folders a Gmsh child may read: the file's own (as named, and where a link leads), and
// those of the libraries already loaded (Gmsh, OpenCASCADE and theirs), for what they load later
std::vector<std::string> readable_folders(const std::string& path) {
  std::vector<std::string> dirs;
  std::error_code ec;
  dirs.push_back(fs::absolute(path, ec).parent_path().string());
  const fs::path real = fs::canonical(path, ec);
  if (!ec) dirs.push_back(real.parent_path().string());
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        // the program itself has no name here; linux-vdso.so.1 no path
        if (info->dlpi_name && info->dlpi_name[0] == '/')
          static_cast<std::vector<std::string>*>(data)->push_back(fs::path(info->dlpi_name).parent_path().string());
        return 0;
      },
      &dirs);
  std::sort(dirs.begin(), dirs.end());
  dirs.erase(std::unique(dirs.begin(), dirs.end()), dirs.end());
  return dirs;
}

// Gmsh element types (gmsh's numbering) and what a shell makes of them
constexpr int kLine2 = 1, kTriangle3 = 2, kQuad4 = 3, kPoint = 15;
std::string element_type_words(int type) {
  switch (type) {
    case 4: return "tetrahedra";
    case 5: return "hexahedra";
    case 6: return "prisms";
    case 7: return "pyramids";
    case 8: return "second-order lines";
    case 9: return "6-node triangles";
    case 10: return "9-node quads";
    case 16: return "8-node quads";
    default: return "elements of Gmsh type " + std::to_string(type);
  }
}

// the area of every 3- and 4-node surface element (a quad by its diagonals' cross product)
double surface_area(const GmshApi& g) {
  int ierr = 0;
  std::size_t* tags = nullptr;
  std::size_t tags_n = 0, coord_n = 0, par_n = 0;
  double* coord = nullptr;
  double* par = nullptr;
  g.get_nodes(&tags, &tags_n, &coord, &coord_n, &par, &par_n, -1, -1, 0, 0, &ierr);
  std::unordered_map<std::size_t, std::size_t> at;
  for (std::size_t k = 0; k < tags_n; ++k) at.emplace(tags[k], 3 * k);
  const auto x = [&](std::size_t tag) {
    const auto it = at.find(tag);
    return it == at.end() ? Eigen::Vector3d::Zero().eval() : Eigen::Vector3d(coord[it->second], coord[it->second + 1], coord[it->second + 2]);
  };
  int* types = nullptr;
  std::size_t types_n = 0, *et_n = nullptr, et_nn = 0, *nt_n = nullptr, nt_nn = 0;
  std::size_t** et = nullptr;
  std::size_t** nt = nullptr;
  g.get_elements(&types, &types_n, &et, &et_n, &et_nn, &nt, &nt_n, &nt_nn, 2, -1, &ierr);
  double area = 0;
  for (std::size_t t = 0; t < types_n; ++t) {
    const int k = types[t] == 2 ? 3 : types[t] == 3 ? 4 : 0;
    for (std::size_t e = 0; k > 0 && e < et_n[t]; ++e) {
      const std::size_t* n = nt[t] + e * k;
      area += k == 3 ? 0.5 * (x(n[1]) - x(n[0])).cross(x(n[2]) - x(n[0])).norm()
                     : 0.5 * (x(n[2]) - x(n[0])).cross(x(n[3]) - x(n[1])).norm();
    }
  }
  return area;
}

// 3-node surface elements in the current mesh
std::size_t count_triangles(const GmshApi& g) {
  int ierr = 0;
  int* types = nullptr;
  std::size_t types_n = 0, *et_n = nullptr, et_nn = 0, *nt_n = nullptr, nt_nn = 0;
  std::size_t** et = nullptr;
  std::size_t** nt = nullptr;
  g.get_elements(&types, &types_n, &et, &et_n, &et_nn, &nt, &nt_n, &nt_nn, 2, -1, &ierr);
  std::size_t n = 0;
  for (std::size_t t = 0; t < types_n; ++t)
    if (types[t] == 2) n += et_n[t];
  return n;
}

// a physical group as the file defines it
struct Physical {
  int dim, tag;
  std::string name;
  std::vector<int> entities;
};

std::string dim_words(int dim) {
  return dim == 0 ? std::string("point") : dim == 1 ? std::string("curve") : dim == 2 ? std::string("surface") : std::string("volume");
}

std::string physical_label(const Physical& p) {
  return "physical " + dim_words(p.dim) + " " + std::to_string(p.tag) + (p.name.empty() ? "" : " '" + p.name + "'");
}

int entity_count(const GmshApi& g, int dim) {
  int ierr = 0;
  int* tags = nullptr;
  std::size_t n = 0;
  g.get_entities(&tags, &n, dim, &ierr);
  return static_cast<int>(n / 2);
}

// The points of named group `p` as Gmsh dim/tag pairs: its own points, or the points bounding its
// curves or surfaces (where a local size is set, and what a mapped grid must not cross)
std::vector<int> group_points(const GmshApi& g, const Physical& p) {
  std::vector<int> dim_tags;
  for (int e : p.entities) dim_tags.push_back(p.dim), dim_tags.push_back(e);
  if (p.dim == 0) return dim_tags;
  int ierr = 0;
  int* points = nullptr;
  std::size_t points_n = 0;
  g.get_boundary(dim_tags.data(), dim_tags.size(), &points, &points_n, 0, 0, 1, &ierr);
  check(g, ierr, "finding the points of group '" + p.name + "'");
  return std::vector<int>(points, points + points_n);
}

// A face bounded by four curves is meshed as a mapped (structured, transfinite) grid of quads, the
// others free. Free meshes of one face at neighbouring sizes differ in topology, so their answers
// scatter instead of converging (a STEP roof at mesh sizes 6, 4.5, 3 gave deflections 0.310, 0.300,
// 0.310 against 0.3015 converged), and a coarser twin says nothing about the error of the run; the
// mapped grids of the same face converge monotonically. Each side gets ceil(length / size)
// elements, the largest along its chain of opposite sides (opposite sides of a grid have the same
// count, and a side shared by two mapped faces links their chains), so a side that is a whole
// number of sizes long is divided exactly (a mid-span node stays a node). A four-sided face keeps
// its free mesh when a mapped grid would go against the scene or the geometry: a point or curve
// embedded in it (a grid cannot pass through it), a local size on its boundary (a grid is uniform
// along each side, which would undo the refinement), or a corner of 135 degrees or more (Gmsh's
// own limit: such a face is a triangle or a pentagon in disguise, and its grid would be skewed).
struct MappedFaces {
  std::string note;      ///< for the part's description ("" when no face has four sides)
  bool applied = false;  ///< some faces are mapped
  bool all = false;      ///< every face is mapped
};
MappedFaces map_four_sided_faces(const GmshApi& g, const GmshMeshRequest& r, const std::vector<Physical>& physicals) {
  int ierr = 0;
  int* faces = nullptr;
  std::size_t faces_n = 0;
  g.get_entities(&faces, &faces_n, 2, &ierr);
  check(g, ierr, "reading its surfaces");
  std::set<int> locally_sized;  // points of the groups with a local size
  for (const auto& [name, size] : r.group_sizes)
    for (const Physical& p : physicals) {
      if (p.name != name) continue;
      const std::vector<int> points = group_points(g, p);
      for (std::size_t k = 0; k + 1 < points.size(); k += 2) locally_sized.insert(points[k + 1]);
    }
  // a curve sampled along its parametrization: its length, and the polyline from its start
  constexpr int kSamples = 64;
  std::map<int, std::vector<Eigen::Vector3d>> polylines;
  const auto polyline = [&](int curve) -> const std::vector<Eigen::Vector3d>& {
    auto it = polylines.find(curve);
    if (it != polylines.end()) return it->second;
    double *lo = nullptr, *hi = nullptr;
    std::size_t lo_n = 0, hi_n = 0;
    g.get_parametrization_bounds(1, curve, &lo, &lo_n, &hi, &hi_n, &ierr);
    check(g, ierr, "reading the parametrization of curve " + std::to_string(curve));
    std::vector<double> t(kSamples + 1);
    for (int k = 0; k <= kSamples; ++k) t[k] = lo[0] + (hi[0] - lo[0]) * k / kSamples;
    double* x = nullptr;
    std::size_t x_n = 0;
    g.get_value(1, curve, t.data(), t.size(), &x, &x_n, &ierr);
    check(g, ierr, "sampling curve " + std::to_string(curve));
    std::vector<Eigen::Vector3d> pts;
    for (std::size_t k = 0; k + 2 < x_n; k += 3) pts.emplace_back(x[k], x[k + 1], x[k + 2]);
    return polylines.emplace(curve, std::move(pts)).first->second;
  };
  const auto length = [](const std::vector<Eigen::Vector3d>& pts) {
    double l = 0.0;
    for (std::size_t k = 1; k < pts.size(); ++k) l += (pts[k] - pts[k - 1]).norm();
    return l;
  };
  std::map<int, int> chain;  // union-find over curves: opposite sides of a mapped face
  const auto root = [&](int c) {
    while (chain.at(c) != c) c = chain[c] = chain.at(chain.at(c));
    return c;
  };
  const auto join = [&](int a, int b) {
    chain.emplace(a, a), chain.emplace(b, b);
    chain[root(a)] = root(b);
  };
  std::vector<std::pair<int, std::array<int, 4>>> mapped;  // face, its sides
  std::size_t four_sided = 0, embedding = 0, sized = 0, cornered = 0;
  for (std::size_t k = 0; k + 1 < faces_n; k += 2) {
    int face[2] = {2, faces[k + 1]};
    int* curves = nullptr;
    std::size_t curves_n = 0;
    g.get_boundary(face, 2, &curves, &curves_n, 0, 1, 0, &ierr);  // oriented, in loop order
    check(g, ierr, "reading the curves of surface " + std::to_string(face[1]));
    if (curves_n != 8) continue;
    ++four_sided;
    int* embedded = nullptr;
    std::size_t embedded_n = 0;
    g.get_embedded(2, face[1], &embedded, &embedded_n, &ierr);
    check(g, ierr, "reading what is embedded in surface " + std::to_string(face[1]));
    if (embedded_n > 0) {
      ++embedding;
      continue;
    }
    int* points = nullptr;
    std::size_t points_n = 0;
    g.get_boundary(face, 2, &points, &points_n, 0, 0, 1, &ierr);
    check(g, ierr, "reading the points of surface " + std::to_string(face[1]));
    bool local = false;
    for (std::size_t j = 0; j + 1 < points_n; j += 2) local = local || locally_sized.count(points[j + 1]) > 0;
    if (local) {
      ++sized;
      continue;
    }
    // the sides in loop order, each polyline run along the loop; the angle at each corner between
    // the side that ends there and the one that starts there
    std::array<int, 4> sides{};
    std::array<std::vector<Eigen::Vector3d>, 4> runs;
    for (int j = 0; j < 4; ++j) {
      sides[j] = std::abs(curves[2 * j + 1]);
      runs[j] = polyline(sides[j]);
      if (curves[2 * j + 1] < 0) std::reverse(runs[j].begin(), runs[j].end());
    }
    bool square_enough = true;
    for (int j = 0; j < 4 && square_enough; ++j) {
      const std::vector<Eigen::Vector3d>& in = runs[j];
      const std::vector<Eigen::Vector3d>& out = runs[(j + 1) % 4];
      if (in.size() < 2 || out.size() < 2 || !(length(in) > 0) || !(length(out) > 0)) {
        square_enough = false;  // a side of no length (a pole): not a grid's side
        break;
      }
      const Eigen::Vector3d back = in[in.size() - 2] - in.back(), ahead = out[1] - out.front();
      const double c = back.dot(ahead) / (back.norm() * ahead.norm());
      square_enough = std::acos(std::clamp(c, -1.0, 1.0)) < 135.0 * std::numbers::pi / 180.0;
    }
    if (!square_enough) {
      ++cornered;
      continue;
    }
    join(sides[0], sides[2]);
    join(sides[1], sides[3]);
    mapped.emplace_back(face[1], sides);
  }
  if (four_sided == 0) return {};
  std::map<int, long long> divisions;  // per chain: the most any of its sides needs
  for (const auto& [face, sides] : mapped)
    for (int c : sides) {
      const double n = std::ceil(length(polyline(c)) / r.mesh_size * (1.0 - 1e-9));
      long long& d = divisions[root(c)];
      d = std::max({d, 1LL, static_cast<long long>(n)});
    }
  for (const auto& [curve, parent] : chain) {
    g.set_transfinite_curve(curve, static_cast<int>(divisions.at(root(curve)) + 1), "Progression", 1.0, &ierr);
    check(g, ierr, "dividing curve " + std::to_string(curve) + " for a mapped grid");
  }
  for (const auto& [face, sides] : mapped) {
    g.set_transfinite_surface(face, "Left", nullptr, 0, &ierr);
    check(g, ierr, "setting a mapped grid on surface " + std::to_string(face));
    g.set_recombine(2, face, &ierr);
    check(g, ierr, "recombining surface " + std::to_string(face));
  }
  const std::size_t all = faces_n / 2;
  std::string note = std::to_string(mapped.size()) + " of " + std::to_string(all) + " faces meshed as mapped grids";
  std::vector<std::string> kept;
  if (embedding > 0) kept.push_back(std::to_string(embedding) + " with an embedded point or curve");
  if (sized > 0) kept.push_back(std::to_string(sized) + " with a local size on its boundary");
  if (cornered > 0) kept.push_back(std::to_string(cornered) + " with a corner of 135 degrees or more");
  if (!kept.empty()) {
    note += "; four-sided but meshed free: ";
    for (std::size_t j = 0; j < kept.size(); ++j) note += (j ? ", " : "") + kept[j];
  }
  return {note + " (part.mesh_pattern)", !mapped.empty(), mapped.size() == all};
}

// CAD faces that touch without sharing an edge (a stiffener's foot standing on a panel face, two
// faces side by side each with an edge of its own) are meshed apart, and the shell comes apart
// there. OpenCASCADE's fragment (general fuse) of every face against the others splits faces and
// edges where they meet and makes each common edge one, so that the mesh shares its nodes there.
// Gmsh forgets the physical groups when the model is synchronized after it, so each is found again
// on the new entities: a surface group by the fragment's map of old faces to new, a curve group as
// the new curves lying on its old curves (a copy of each is kept for that search), a point group
// at its old place. Returns a note for the part's description ("" when nothing changed).
std::string join_touching_faces(const GmshApi& g, std::vector<Physical>& physicals) {
  int ierr = 0;
  int* solids = nullptr;
  std::size_t solids_n = 0;
  g.occ_get_entities(&solids, &solids_n, 3, &ierr);
  int* faces = nullptr;
  std::size_t faces_n = 0;
  g.occ_get_entities(&faces, &faces_n, 2, &ierr);
  // one face cannot touch another (and OpenCASCADE refuses to fragment it); faces that bound a
  // solid share their edges already, and fragmenting them would leave the solid behind
  if (ierr != 0 || solids_n > 0 || faces_n < 4) return {};
  const std::vector<int> face_dim_tags(faces, faces + faces_n);
  const int faces_before = entity_count(g, 2), curves_before = entity_count(g, 1);
  double box[6];
  g.get_bounding_box(-1, -1, &box[0], &box[1], &box[2], &box[3], &box[4], &box[5], &ierr);
  check(g, ierr, "measuring its geometry");
  const double tol = 1e-6 * Eigen::Vector3d(box[3] - box[0], box[4] - box[1], box[5] - box[2]).norm();

  std::map<int, Eigen::Vector3d> point_at;  // grouped point -> where it was
  std::map<int, int> copy_of;               // grouped curve -> a copy of it
  for (const Physical& p : physicals)
    for (int e : p.entities) {
      if (p.dim == 0 && !point_at.count(e)) {
        double* x = nullptr;
        std::size_t n = 0;
        g.get_value(0, e, nullptr, 0, &x, &n, &ierr);
        check(g, ierr, "reading the place of point " + std::to_string(e));
        if (n == 3) point_at[e] = Eigen::Vector3d(x[0], x[1], x[2]);
      }
      if (p.dim == 1 && !copy_of.count(e)) {
        int dim_tag[2] = {1, e};
        int* out = nullptr;
        std::size_t out_n = 0;
        g.occ_copy(dim_tag, 2, &out, &out_n, &ierr);
        check(g, ierr, "keeping curve " + std::to_string(e) + " of " + physical_label(p));
        if (out_n == 2) copy_of[e] = out[1];
      }
    }

  int* out = nullptr;
  std::size_t out_n = 0;
  int** map = nullptr;
  std::size_t* map_n = nullptr;
  std::size_t map_nn = 0;
  g.occ_fragment(const_cast<int*>(face_dim_tags.data()), face_dim_tags.size(), nullptr, 0, &out, &out_n, &map, &map_n,
                 &map_nn, -1, 1, 1, &ierr);
  const bool fragmented = ierr == 0 && map_nn == face_dim_tags.size() / 2;
  const std::string failure = ierr != 0 ? g.why() : std::string();
  g.occ_synchronize(&ierr);
  check(g, ierr, "joining its faces");

  std::map<int, std::vector<int>> faces_of;  // old face -> the faces it became
  for (std::size_t k = 0; k < face_dim_tags.size() / 2; ++k) {
    const int old = face_dim_tags[2 * k + 1];
    if (!fragmented) {
      faces_of[old] = {old};
      continue;
    }
    for (std::size_t m = 0; m + 1 < map_n[k]; m += 2)
      if (map[k][m] == 2) faces_of[old].push_back(map[k][m + 1]);
  }
  // every new curve (not a copy) at two inner points, against each grouped curve's copy
  std::vector<int> copies;
  for (const auto& [old, copy] : copy_of) copies.push_back(copy);
  std::map<int, std::vector<int>> curves_of;  // old curve -> the new curves on it
  if (!copy_of.empty()) {
    int* curves = nullptr;
    std::size_t curves_n = 0;
    g.get_entities(&curves, &curves_n, 1, &ierr);
    for (std::size_t k = 0; k + 1 < curves_n; k += 2) {
      const int c = curves[k + 1];
      if (std::find(copies.begin(), copies.end(), c) != copies.end()) continue;
      double *lo = nullptr, *hi = nullptr;
      std::size_t lo_n = 0, hi_n = 0;
      g.get_parametrization_bounds(1, c, &lo, &lo_n, &hi, &hi_n, &ierr);
      if (ierr != 0 || lo_n != 1 || hi_n != 1) continue;
      std::vector<double> inner;
      for (double f : {0.3, 0.7}) {
        const double t = lo[0] + f * (hi[0] - lo[0]);
        double* x = nullptr;
        std::size_t n = 0;
        g.get_value(1, c, const_cast<double*>(&t), 1, &x, &n, &ierr);
        if (ierr == 0 && n == 3) inner.insert(inner.end(), x, x + 3);
      }
      if (inner.size() != 6) continue;
      for (const auto& [old, copy] : copy_of) {
        double *near = nullptr, *par = nullptr;
        std::size_t near_n = 0, par_n = 0;
        g.get_closest_point(1, copy, inner.data(), inner.size(), &near, &near_n, &par, &par_n, &ierr);
        if (ierr != 0 || near_n != 6) continue;
        bool on = true;
        for (int a = 0; a < 2; ++a)
          on = on && Eigen::Vector3d(near[3 * a] - inner[3 * a], near[3 * a + 1] - inner[3 * a + 1],
                                     near[3 * a + 2] - inner[3 * a + 2]).norm() <= tol;
        if (on) curves_of[old].push_back(c);
      }
    }
    std::vector<int> copy_dim_tags;
    for (int c : copies) copy_dim_tags.push_back(1), copy_dim_tags.push_back(c);
    g.occ_remove(copy_dim_tags.data(), copy_dim_tags.size(), 1, &ierr);
    check(g, ierr, "removing the curves kept for the groups");
    g.occ_synchronize(&ierr);
    check(g, ierr, "joining its faces");
  }

  g.remove_physical_groups(nullptr, 0, &ierr);
  for (Physical& p : physicals) {
    std::vector<int> now;
    for (int e : p.entities) {
      const std::vector<int>* found = p.dim == 2 ? &faces_of[e] : p.dim == 1 ? &curves_of[e] : nullptr;
      if (found) now.insert(now.end(), found->begin(), found->end());
      if (p.dim == 0 && point_at.count(e)) {
        const Eigen::Vector3d& x = point_at[e];
        int* tags = nullptr;
        std::size_t n = 0;
        g.get_entities_in_bounding_box(x.x() - tol, x.y() - tol, x.z() - tol, x.x() + tol, x.y() + tol, x.z() + tol, &tags,
                                       &n, 0, &ierr);
        for (std::size_t k = 0; k + 1 < n; k += 2) now.push_back(tags[k + 1]);
      }
    }
    std::sort(now.begin(), now.end());
    now.erase(std::unique(now.begin(), now.end()), now.end());
    if (now.empty() && !p.entities.empty())
      throw GmshFailure(physical_label(p) + " was lost when its faces were joined where they touch (OpenCASCADE's "
                        "fragment); part.keep_faces_apart = true leaves the faces as they are");
    g.add_physical_group(p.dim, now.data(), now.size(), p.tag, &ierr);
    check(g, ierr, "keeping " + physical_label(p));
    if (!p.name.empty()) g.set_physical_name(p.dim, p.tag, p.name.c_str(), &ierr);
    p.entities = std::move(now);
  }
  if (!fragmented)
    return "CAD faces not joined where they touch: OpenCASCADE's fragment failed (" + failure + ")";
  const int faces_after = entity_count(g, 2), curves_after = entity_count(g, 1);
  bool changed = faces_after != faces_before || curves_after != curves_before;
  for (const auto& [old, now] : faces_of) changed = changed || now.size() != 1 || now[0] != old;
  if (!changed) return {};
  return "CAD faces joined where they touch (OpenCASCADE's fragment: " + std::to_string(faces_before) + " faces and " +
         std::to_string(curves_before) + " edges became " + std::to_string(faces_after) + " and " +
         std::to_string(curves_after) + ")";
}

// The area of the geometry's surfaces, before they are meshed: OpenCASCADE's own (exact, trims
// included) for its entities (STEP, IGES, BREP, a .geo on that kernel); otherwise the integral of
// |x_u x x_v| over the surface's parameter rectangle on a 16 x 16 grid (exact for a plane; a
// trimmed surface's whole rectangle, so more than its area). A surface with neither counts 0.
double geometry_area(const GmshApi& g) {
  int ierr = 0;
  int* occ = nullptr;
  std::size_t occ_n = 0;
  g.occ_get_entities(&occ, &occ_n, 2, &ierr);
  std::set<int> occ_surfaces;
  for (std::size_t k = 0; ierr == 0 && k + 1 < occ_n; k += 2) occ_surfaces.insert(occ[k + 1]);
  int* surfs = nullptr;
  std::size_t surfs_n = 0;
  g.get_entities(&surfs, &surfs_n, 2, &ierr);
  double area = 0;
  for (std::size_t k = 0; k + 1 < surfs_n; k += 2) {
    const int tag = surfs[k + 1];
    if (occ_surfaces.count(tag)) {
      double mass = 0;
      g.occ_get_mass(2, tag, &mass, &ierr);
      if (ierr == 0 && std::isfinite(mass) && mass > 0) {
        area += mass;
        continue;
      }
    }
    double *lo = nullptr, *hi = nullptr;
    std::size_t lo_n = 0, hi_n = 0;
    g.get_parametrization_bounds(2, tag, &lo, &lo_n, &hi, &hi_n, &ierr);
    if (ierr != 0 || lo_n != 2 || hi_n != 2) continue;
    constexpr int n = 16;
    std::vector<double> uv;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) uv.push_back(lo[0] + (hi[0] - lo[0]) * i / n), uv.push_back(lo[1] + (hi[1] - lo[1]) * j / n);
    double* xyz = nullptr;
    std::size_t xyz_n = 0;
    g.get_value(2, tag, uv.data(), uv.size(), &xyz, &xyz_n, &ierr);
    if (ierr != 0 || xyz_n != 3 * uv.size() / 2) continue;
    const auto x = [&](int i, int j) { return Eigen::Vector3d(xyz + 3 * (j * (n + 1) + i)); };
    double a = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) a += 0.5 * (x(i + 1, j + 1) - x(i, j)).cross(x(i, j + 1) - x(i + 1, j)).norm();
    if (std::isfinite(a)) area += a;
  }
  return area;
}

// The longest element of Gmsh's mesh of the curves (meshed here, at the script's own sizes; the
// surface mesh then starts from it): the size a surface's elements do not exceed when nothing
// but its boundary sets them
double longest_curve_element(const GmshApi& g) {
  int ierr = 0;
  g.generate(1, &ierr);
  check(g, ierr, "Gmsh could not mesh its curves");
  std::size_t* tags = nullptr;
  std::size_t tags_n = 0, coord_n = 0, par_n = 0;
  double* coord = nullptr;
  double* par = nullptr;
  g.get_nodes(&tags, &tags_n, &coord, &coord_n, &par, &par_n, -1, -1, 0, 0, &ierr);
  std::unordered_map<std::size_t, Eigen::Vector3d> at;
  for (std::size_t k = 0; k < tags_n; ++k) at.emplace(tags[k], Eigen::Vector3d(coord + 3 * k));
  int* types = nullptr;
  std::size_t types_n = 0, *et_n = nullptr, et_nn = 0, *nt_n = nullptr, nt_nn = 0;
  std::size_t** et = nullptr;
  std::size_t** nt = nullptr;
  g.get_elements(&types, &types_n, &et, &et_n, &et_nn, &nt, &nt_n, &nt_nn, 1, -1, &ierr);
  double longest = 0;
  for (std::size_t t = 0; t < types_n; ++t)
    for (std::size_t e = 0; types[t] == kLine2 && e < et_n[t]; ++e) {
      const auto a = at.find(nt[t][2 * e]), b = at.find(nt[t][2 * e + 1]);
      if (a != at.end() && b != at.end()) longest = std::max(longest, (a->second - b->second).norm());
    }
  return longest;
}

// Refuses geometry whose mesh would have more nodes than a run can hold (r.most_nodes, from the
// scene's memory estimate) before Gmsh spends minutes and gigabytes meshing it: about its
// surfaces' area over the element size squared (quads of a Frontal-Delaunay mesh recombined are a
// little smaller than size x size, so this is at most the count, give or take a trimmed surface)
void refuse_oversized_geometry(const GmshApi& g, const GmshMeshRequest& r) {
  if (!(r.most_nodes > 0)) return;
  const double area = geometry_area(g);
  if (!(area > 0)) return;
  const bool scene_size = r.mesh_size > 0;
  const double size = scene_size ? r.mesh_size : longest_curve_element(g);
  if (!(size > 0)) return;
  const double quads = area / (size * size);
  if (quads <= r.most_nodes) return;
  char text[320];
  std::snprintf(text, sizeof text,
                "Gmsh would mesh it into about %.3g quads (its surfaces' area %.4g over the square of %s %.4g), more "
                "than the about %.3g nodes a run can hold within the %s this machine allows (the scene's memory "
                "estimate); ",
                quads, area, scene_size ? "part.mesh_size =" : "the longest element of Gmsh's mesh of its curves,",
                size, r.most_nodes, input_bytes_words(r.memory_limit_bytes).c_str());
  throw GmshFailure(std::string(text) + (scene_size ? "raise part.mesh_size" : "give a part.mesh_size, or larger sizes in the script"));
}

// Meshes the file's geometry at the scene's sizes (which win over the script's global size
// settings), mapped grids on four-sided faces where asked, quads only; what it did goes to `notes`.
void mesh_the_geometry(const GmshApi& g, const GmshMeshRequest& r, const std::vector<Physical>& physicals,
                       std::vector<std::string>& notes) {
  int ierr = 0;
  bool subdivided = false;
  // The scene's sizes win over the script's global size settings, which would otherwise undo
  // them silently (a Mesh.MeshSizeMin of 2 made local sizes 2, 1 and 0.5 one mesh). Gmsh takes at
  // each point the smallest size from points, curvature and fields, clamps it to [MeshSizeMin,
  // MeshSizeMax] and multiplies it by MeshSizeFactor: the scene's sizes are set as point sizes
  // divided by the script's factor, a minimum above the smallest of them is lowered to it, and
  // point sizes are switched on. A local size above the script's cap is refused (the cap is
  // the script's wish for every element; part.mesh_size replaces it).
  const auto option = [&](const char* name) {
    double v = 0.0;
    g.get_number(name, &v, &ierr);
    check(g, ierr, std::string("reading ") + name);
    return v;
  };
  const double script_factor = option("Mesh.MeshSizeFactor"), script_min = option("Mesh.MeshSizeMin"),
               script_max = option("Mesh.MeshSizeMax");
  const bool scene_sizes = r.mesh_size > 0 || !r.group_sizes.empty();
  if (scene_sizes) {
    if (!(script_factor > 0)) throw GmshFailure("its Mesh.MeshSizeFactor is " + significant(script_factor) + ", not > 0");
    double smallest = r.mesh_size > 0 ? r.mesh_size : std::numeric_limits<double>::infinity();
    for (const auto& [name, size] : r.group_sizes) {
      smallest = std::min(smallest, size);
      if (!(r.mesh_size > 0) && size > script_max * script_factor)
        throw GmshFailure("part.local_sizes asks " + significant(size) + " at group '" + name + "', above the script's "
                          "largest element (Mesh.MeshSizeMax " + significant(script_max) +
                          (script_factor != 1 ? " x Mesh.MeshSizeFactor " + significant(script_factor) : std::string()) +
                          "): a local size is finer than the rest; give a smaller one, or part.mesh_size (which "
                          "replaces the script's largest element)");
    }
    if (script_min * script_factor > smallest) {
      g.set_number("Mesh.MeshSizeMin", smallest / script_factor, &ierr);
      notes.push_back("the script's Mesh.MeshSizeMin " + significant(script_min) + " lowered to " +
                      significant(smallest / script_factor) + " so that the scene's sizes are reached");
    }
    if (option("Mesh.MeshSizeFromPoints") == 0) {
      g.set_number("Mesh.MeshSizeFromPoints", 1, &ierr);
      notes.push_back("the script's Mesh.MeshSizeFromPoints = 0 set to 1 (the scene's sizes are point sizes)");
    }
    if (script_factor != 1)
      notes.push_back("the script's Mesh.MeshSizeFactor " + significant(script_factor) + " kept for its own sizes, the "
                      "scene's set so that they come out as given");
  }
  if (r.mesh_size > 0) {  // at every point (a CAD file's points carry no sizes, and Gmsh would give
                          // them a tenth of the part's diagonal, which a cap alone only lowers) and as the cap
    g.set_number("Mesh.MeshSizeMax", r.mesh_size / script_factor, &ierr);
    int* points = nullptr;
    std::size_t points_n = 0;
    g.get_entities(&points, &points_n, 0, &ierr);
    check(g, ierr, "reading its points");
    if (points_n > 0) g.set_size(points, points_n, r.mesh_size / script_factor, &ierr);
    check(g, ierr, "setting its size");
  }
  for (const auto& [name, size] : r.group_sizes) {  // each named group's points at its own size
    const auto it = std::find_if(physicals.begin(), physicals.end(), [&](const Physical& p) { return p.name == name; });
    if (it == physicals.end())
      throw GmshFailure("part.local_size_groups names group '" + name + "', which the file does not define");
    std::vector<int> points = group_points(g, *it);
    g.set_size(points.data(), points.size(), size / script_factor, &ierr);
    check(g, ierr, "setting the size of group '" + name + "'");
  }
  refuse_oversized_geometry(g, r);
  // Frontal-Delaunay (6) with Blossom recombination: robust in Gmsh 4.8, where the quad-dedicated
  // Frontal-Delaunay for quads (8) segfaulted on a cylindrical roof
  g.set_number("Mesh.Algorithm", 6, &ierr);
  g.set_number("Mesh.RecombineAll", 1, &ierr);
  g.set_number("Mesh.RecombinationAlgorithm", 1, &ierr);
  g.set_number("Mesh.ElementOrder", 1, &ierr);
  MappedFaces mapped;
  if (r.mapped_faces && r.mesh_size > 0) mapped = map_four_sided_faces(g, r, physicals);
  g.generate(2, &ierr);
  check(g, ierr, "Gmsh could not mesh it");
  // Blossom can leave a few triangles (a hemisphere at size 0.35 left 2 of 1467 elements), and
  // one triangle would make FlexFrame split every element of the part. Then the part is meshed
  // at twice the size and Gmsh subdivides every element into quads (Mesh.SubdivisionAlgorithm =
  // 1), its new nodes on the CAD surface. (The full-quad recombinations 2 and 3 refuse periodic
  // surfaces such as a sphere in Gmsh 4.8.)
  if (count_triangles(g) > 0) {
    g.clear(nullptr, 0, &ierr);
    check(g, ierr, "clearing a mesh with triangles");
    g.set_number("Mesh.MeshSizeFactor", 2.0 * script_factor, &ierr);  // every size, the script's and the scene's
    g.set_number("Mesh.SubdivisionAlgorithm", 1, &ierr);
    g.generate(2, &ierr);
    check(g, ierr, "Gmsh could not mesh it into quads only");
    subdivided = true;
  }
  if (!mapped.note.empty()) notes.push_back(mapped.note);
  notes.push_back(std::string(mapped.all                 ? "meshed by Gmsh as structured quads"
                              : mapped.applied       ? "the other faces meshed by Gmsh 2D Frontal-Delaunay with "
                                                       "Blossom recombination"
                                                     : "meshed by Gmsh 2D Frontal-Delaunay with Blossom recombination") +
                  (subdivided ? " at twice the size, then every element subdivided into quads (plain Blossom left "
                                "triangles), "
                              : ", ") +
                  (r.mesh_size > 0 ? "elements at most " + significant(r.mesh_size) + " across" : std::string("the file's sizes")));
}

// Everything the child does with Gmsh; throws GmshFailure with a sentence. `unconfined` says
// what the sandbox could not confine ("" when it confined all), for the notes.
void mesh_in_child(const GmshApi& g, const GmshMeshRequest& r, Writer& w, const std::string& unconfined) {
  int ierr = 0;
  g.initialize(0, nullptr, 0, &ierr);
  check(g, ierr, "Gmsh did not start");
  g.logger_start(&ierr);
  g.set_number("General.Terminal", 0, &ierr);
  g.set_number("General.AbortOnError", 0, &ierr);
  g.open(r.path.c_str(), &ierr);
  check(g, ierr, "Gmsh could not read it");
  // a reader that meets a malformed file, or a script command that the sandbox refused (Save,
  // System), logs an error and goes on: any error while reading is the file's fault
  if (const std::string e = g.first_logged_error(); !e.empty()) throw GmshFailure("Gmsh could not read it: " + e +
                       (lower_extension(r.path) != ".geo" ? ""
                        : unconfined.empty()
                            ? " (FlexFrame runs .geo scripts read-only, and lets them read only the files in their own "
                              "folder and below: a script may not write files, run commands or read other files)"
                            : " (FlexFrame runs .geo scripts read-only: a script may not write files or run commands)"));

  // physical groups, read before meshing (their entities carry the per-group sizes)
  int* pg = nullptr;
  std::size_t pg_n = 0;
  g.get_physical_groups(&pg, &pg_n, -1, &ierr);
  check(g, ierr, "reading its physical groups");
  std::vector<Physical> physicals;
  for (std::size_t k = 0; k + 1 < pg_n; k += 2) {
    Physical p{pg[k], pg[k + 1], {}, {}};
    char* name = nullptr;
    g.get_physical_name(p.dim, p.tag, &name, &ierr);
    p.name = name && *name ? name : "";
    int* ents = nullptr;
    std::size_t ents_n = 0;
    g.get_entities_for_physical_group(p.dim, p.tag, &ents, &ents_n, &ierr);
    check(g, ierr, "reading the entities of physical group " + std::to_string(p.tag));
    p.entities.assign(ents, ents + ents_n);
    physicals.push_back(std::move(p));
  }

  std::vector<std::string> notes;
  if (!unconfined.empty()) notes.push_back(unconfined);
  if (r.mesh_geometry && r.join_touching_faces)
    if (std::string joined = join_touching_faces(g, physicals); !joined.empty()) notes.push_back(std::move(joined));
  if (r.mesh_geometry) {
    mesh_the_geometry(g, r, physicals, notes);
  } else if (r.recombine_triangles) {
    const double before = surface_area(g);
    g.recombine(&ierr);
    check(g, ierr, "Gmsh could not recombine its triangles");
    const double after = surface_area(g);
    // Gmsh 4.8 broke an STL surface this way (2 elements left of 42 triangles): refused, not used
    if (!(std::abs(after - before) <= 1e-9 * before))
      throw GmshFailure("Gmsh's recombination changed the surface's area from " + std::to_string(before) + " to " +
                        std::to_string(after) + "; use part.triangles = \"split\"");
    notes.push_back("triangles recombined into quads by Gmsh (Blossom)");
  }

  // nodes
  std::size_t* tags = nullptr;
  std::size_t tags_n = 0, coord_n = 0, par_n = 0;
  double* coord = nullptr;
  double* par = nullptr;
  g.get_nodes(&tags, &tags_n, &coord, &coord_n, &par, &par_n, -1, -1, 0, 0, &ierr);
  check(g, ierr, "reading its nodes");
  std::unordered_map<std::size_t, int> index;
  std::vector<double> xyz(coord, coord + coord_n);
  for (std::size_t k = 0; k < tags_n; ++k) index.emplace(tags[k], static_cast<int>(k));
  const auto node = [&](std::size_t tag) {
    const auto it = index.find(tag);
    if (it == index.end()) throw GmshFailure("an element names node " + std::to_string(tag) + ", which the file does not define");
    return it->second;
  };

  // volumes are not shells
  int* vols = nullptr;
  std::size_t vols_n = 0;
  g.get_entities(&vols, &vols_n, 3, &ierr);
  for (std::size_t k = 0; k + 1 < vols_n; k += 2) {
    int* types = nullptr;
    std::size_t types_n = 0, *et_n = nullptr, et_nn = 0, *nt_n = nullptr, nt_nn = 0;
    std::size_t** et = nullptr;
    std::size_t** nt = nullptr;
    g.get_elements(&types, &types_n, &et, &et_n, &et_nn, &nt, &nt_n, &nt_nn, 3, vols[k + 1], &ierr);
    if (types_n > 0)
      throw GmshFailure("volume " + std::to_string(vols[k + 1]) + " holds " + element_type_words(types[0]) +
                        ": a shell is a surface mesh; export only the surface (or its mid-surface)");
  }

  // surface elements, entity by entity; exact normals where the surface is CAD geometry
  int* surfs = nullptr;
  std::size_t surfs_n = 0;
  g.get_entities(&surfs, &surfs_n, 2, &ierr);
  check(g, ierr, "reading its surfaces");
  std::vector<std::int32_t> elem_nodes, elem_entity;
  std::vector<std::int64_t> elem_tag;
  std::vector<double> normals;  // 12 per element when exact
  std::map<std::size_t, int> element_index;  // Gmsh tag -> our index
  bool exact = r.mesh_geometry;
  for (std::size_t s = 0; s + 1 < surfs_n; s += 2) {
    const int tag = surfs[s + 1];
    int* types = nullptr;
    std::size_t types_n = 0, *et_n = nullptr, et_nn = 0, *nt_n = nullptr, nt_nn = 0;
    std::size_t** et = nullptr;
    std::size_t** nt = nullptr;
    g.get_elements(&types, &types_n, &et, &et_n, &et_nn, &nt, &nt_n, &nt_nn, 2, tag, &ierr);
    check(g, ierr, "reading the elements of surface " + std::to_string(tag));
    char* type_name = nullptr;
    g.get_type(2, tag, &type_name, &ierr);
    const bool discrete = !type_name || std::strstr(type_name, "Discrete") != nullptr;
    if (discrete) exact = false;
    for (std::size_t t = 0; t < types_n; ++t) {
      const int k = types[t] == kTriangle3 ? 3 : types[t] == kQuad4 ? 4 : 0;
      if (k == 0)
        throw GmshFailure("surface " + std::to_string(tag) + " holds " + element_type_words(types[t]) +
                          ": FlexFrame's shell element takes 3- and 4-node elements (set Mesh.ElementOrder = 1)");
      for (std::size_t e = 0; e < et_n[t]; ++e) {
        std::array<std::int32_t, 4> n{-1, -1, -1, -1};
        for (int a = 0; a < k; ++a) n[a] = node(nt[t][e * k + a]);
        element_index[et[t][e]] = static_cast<int>(elem_tag.size());
        elem_nodes.insert(elem_nodes.end(), n.begin(), n.end());
        elem_entity.push_back(tag);
        elem_tag.push_back(static_cast<std::int64_t>(et[t][e]));
        if (exact && !discrete) {
          std::vector<double> c;
          for (int a = 0; a < 4; ++a) {
            const int id = n[a < k ? a : 0];
            c.insert(c.end(), {xyz[3 * id], xyz[3 * id + 1], xyz[3 * id + 2]});
          }
          double* uv = nullptr;
          std::size_t uv_n = 0;
          g.get_parametrization(2, tag, c.data(), c.size(), &uv, &uv_n, &ierr);
          double* nn = nullptr;
          std::size_t nn_n = 0;
          if (ierr == 0 && uv_n == 8) g.get_normal(tag, uv, uv_n, &nn, &nn_n, &ierr);
          if (ierr != 0 || nn_n != 12) {
            exact = false;
          } else {
            normals.insert(normals.end(), nn, nn + 12);
          }
        }
      }
    }
  }
  if (elem_tag.empty()) throw GmshFailure("it holds no surface elements (no triangles or quads on any surface)");
  for (double v : normals)
    if (!std::isfinite(v)) exact = false;
  if (!exact) normals.clear();

  // groups
  w.put<std::uint8_t>(1);
  w.put_array(xyz);
  w.put_array(elem_nodes);
  w.put_array(elem_entity);
  w.put_array(elem_tag);
  w.put_array(normals);
  w.put<std::uint64_t>(physicals.size());
  for (const Physical& p : physicals) {
    if (p.dim == 3) throw GmshFailure(physical_label(p) + " is a volume group; a shell mesh has no volumes");
    w.put_string(p.name.empty() ? std::to_string(p.tag) : p.name);
    w.put<std::int32_t>(p.dim);
    w.put_string(physical_label(p));
    std::size_t* nt = nullptr;
    std::size_t nt_n = 0, c_n = 0;
    double* c = nullptr;
    g.get_nodes_for_physical_group(p.dim, p.tag, &nt, &nt_n, &c, &c_n, &ierr);
    check(g, ierr, "reading the nodes of " + physical_label(p));
    std::vector<std::int32_t> nodes;
    // a surface group is its elements (their corners are its nodes); a curve or point group its nodes
    if (p.dim != 2)
      for (std::size_t k = 0; k < nt_n; ++k) nodes.push_back(node(nt[k]));
    std::vector<std::int32_t> elements, segments;
    for (int entity : p.entities) {
      int* types = nullptr;
      std::size_t types_n = 0, *et_n = nullptr, et_nn = 0, *ntn = nullptr, nt_nn = 0;
      std::size_t** et = nullptr;
      std::size_t** ntt = nullptr;
      g.get_elements(&types, &types_n, &et, &et_n, &et_nn, &ntt, &ntn, &nt_nn, p.dim, entity, &ierr);
      check(g, ierr, "reading the elements of " + physical_label(p));
      for (std::size_t t = 0; t < types_n; ++t) {
        if (p.dim == 2)
          for (std::size_t e = 0; e < et_n[t]; ++e) elements.push_back(element_index.at(et[t][e]));
        if (p.dim == 1 && types[t] == kLine2)
          for (std::size_t e = 0; e < et_n[t]; ++e)
            segments.push_back(node(ntt[t][2 * e])), segments.push_back(node(ntt[t][2 * e + 1]));
        if (p.dim == 0 && types[t] != kPoint) continue;
      }
    }
    w.put_array(nodes);
    w.put_array(elements);
    w.put_array(segments);
  }
  w.put<std::uint64_t>(notes.size());
  for (const std::string& n : notes) w.put_string(n);
}

[[noreturn]] void child_main(int fd, const GmshMeshRequest& r, pid_t parent) {
  // The child dies with its parent: a flexframe ended by SIGKILL (a batch system's hard stop, the
  // OOM killer) must not leave Gmsh meshing on, its time limit gone with the parent that enforced
  // it. The signal comes when the thread that forked ends, which waits for this child to end
  // (read_with_gmsh); should the parent have died before prctl, this child now has another parent.
  if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(4);
  // Gmsh and OpenCASCADE print to stdout and stderr: the run's own output must stay clean
  const int devnull = ::open("/dev/null", O_RDWR);
  if (devnull >= 0) dup2(devnull, 0), dup2(devnull, 1), dup2(devnull, 2);
  // only the pipe stays open: no descriptor of the parent's (a results file) is reachable
  if (fd != 3) {
    dup2(fd, 3);
    fd = 3;
  }
  syscall(SYS_close_range, 4u, ~0u, 0u);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  constexpr bool sanitized = true;  // a sanitizer's shadow memory spans terabytes: no address-space limit
#else
  constexpr bool sanitized = false;
#endif
  if (r.memory_limit_bytes > 0 && !sanitized) {
    const rlim_t limit = static_cast<rlim_t>(r.memory_limit_bytes);
    rlimit lim{limit, limit};
    setrlimit(RLIMIT_AS, &lim);
  }
  Writer w;
  GmshApi g;
  std::string problem = g.load();
  const bool script = lower_extension(r.path) == ".geo";
  // Nothing the child reads may come from outside the file's folder: an empty environment (a
  // script's GetEnv("HOME") reads ""; Gmsh needs none, its libraries are loaded), and reads
  // confined to the file's folder and the libraries' (Landlock) where the kernel offers it.
  clearenv();
  const std::vector<std::string> readable = readable_folders(r.path);
  const std::string unconfined = problem.empty() ? confine_reads(readable) : std::string();
  // a .geo script is a program and runs only inside the sandbox; a data file (.msh, STEP, IGES,
  // BREP) has no commands, and is still read in this child (crashes and time bounded) where the
  // kernel offers no seccomp filter (some containers)
  if (problem.empty() && !enter_read_only_sandbox() && script)
    problem = "the kernel refused the read-only sandbox in which FlexFrame runs Gmsh scripts, so the .geo script "
              "is not run (a script can write files and run commands); give its geometry as STEP or BREP instead";
  if (problem.empty()) {
    try {
      mesh_in_child(g, r, w, script && !unconfined.empty()
                                 ? "the .geo script could read any file this user may read (" + unconfined + ")"
                                 : std::string());
    } catch (const GmshFailure& e) {
      problem = e.what();
    } catch (const std::bad_alloc&) {
      problem = "Gmsh ran out of the memory this machine allows";
    } catch (const std::exception& e) {
      problem = std::string("Gmsh failed: ") + e.what();
    } catch (const std::string& e) {  // Gmsh's C++ core throws strings
      problem = "Gmsh failed: " + e;
    } catch (...) {
      problem = "Gmsh failed with an unknown exception";
    }
  }
  if (!problem.empty()) {
    w.bytes.clear();
    w.put<std::uint8_t>(0);
    w.put_string(problem);
  }
  const char* p = w.bytes.data();
  std::size_t left = w.bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) _exit(3);
    p += n, left -= static_cast<std::size_t>(n);
  }
  _exit(0);
}

// ---- a .msh file's claims, checked in the parent before Gmsh reads it ------------------------------
// Gmsh allocates for the counts of a .msh file's $Nodes and $Elements headers as it meets them: a
// 1.6 kB file whose $Nodes header claimed 10^9 nodes took the child past 13 GB. The parent reads
// $MeshFormat and those two headers (formats 2 and 4, ASCII and binary) and refuses a claim the
// bytes after its header cannot hold, or whose reading would not fit in the memory limit.

// Peak bytes of reading a .msh, per node and per element: Gmsh 4.8 read a v4.1 ASCII file of
// 1.0 M nodes and 1.0 M quads in 190 MB more than it started with (about 100 bytes a node and
// 100 an element), the child's copies out of Gmsh's API as much again, and the import's own
// (mesh_import.cpp: 250 a vertex, 400 a face).
constexpr double kMshBytesPerNode = 450.0, kMshBytesPerElement = 600.0;

// a file read in pieces, line by line or byte by byte: memory bounded whatever the file holds
class MshScan {
 public:
  explicit MshScan(int fd) : fd_(fd) {}
  /// The next line without its end ("\n" or "\r\n"), at most `most` bytes of it; false at the end.
  bool line(std::string& out, std::size_t most = 256) {
    out.clear();
    bool any = false;
    while (at_ < buf_.size() || fill()) {
      any = true;
      const char* start = buf_.data() + at_;
      const char* nl = static_cast<const char*>(std::memchr(start, '\n', buf_.size() - at_));
      const std::size_t len = nl ? static_cast<std::size_t>(nl - start) : buf_.size() - at_;
      out.append(start, std::min(len, most - std::min(most, out.size())));
      at_ += len + (nl ? 1 : 0);
      offset_ += len + (nl ? 1 : 0);
      if (nl) {
        ++line_;
        break;
      }
    }
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return any;
  }
  /// The next n bytes; false when the file ends first.
  bool bytes(void* out, std::size_t n) {
    while (buf_.size() - at_ < n)
      if (!fill()) return false;
    std::memcpy(out, buf_.data() + at_, n);
    at_ += n;
    offset_ += n;
    return true;
  }
  std::uint64_t offset() const { return offset_; }  ///< bytes read so far
  int line_number() const { return line_; }          ///< of the line that comes next

 private:
  bool fill() {
    buf_.erase(0, at_);
    at_ = 0;
    char chunk[1 << 16];
    while (true) {
      const ssize_t n = ::read(fd_, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      buf_.append(chunk, static_cast<std::size_t>(n));
      return true;
    }
  }
  int fd_;
  std::string buf_;
  std::size_t at_ = 0;
  std::uint64_t offset_ = 0;
  int line_ = 1;
};

bool check_msh_claims(const std::string& path, const std::string& who, double memory_limit, std::string* error) {
  std::uintmax_t size = 0;
  std::string problem;
  const int fd = open_input_file(path, 0, "", &problem, &size);
  if (fd < 0) return fail(error, who + " " + problem);
  struct Closer {
    int fd;
    ~Closer() { close(fd); }
  } closer{fd};
  MshScan in(fd);
  std::string line;
  if (!in.line(line) || line != "$MeshFormat" || !in.line(line)) return true;  // not format 2 or 4: Gmsh says what it is
  double version = 0;
  int binary = 0, data_size = 0;
  if (std::sscanf(line.c_str(), "%lf %d %d", &version, &binary, &data_size) != 3) return true;
  const bool v4 = version >= 4;
  // a count in a section header: text, except the size_t words of format 4's binary headers
  const auto count = [&](double& n) {
    if (binary && v4) {
      // the number of entity blocks, of nodes or elements, and (4.1) the smallest and largest tag
      std::uint64_t words[4] = {0, 0, 0, 0};
      if (data_size != 8 || !in.bytes(words, (version >= 4.1 ? 4 : 2) * sizeof(std::uint64_t))) return false;
      n = static_cast<double>(words[1]);
      return true;
    }
    if (!in.line(line)) return false;
    double blocks = 0;
    return v4 ? std::sscanf(line.c_str(), "%lf %lf", &blocks, &n) == 2 : std::sscanf(line.c_str(), "%lf", &n) == 1;
  };
  // the fewest bytes a node and an element take after their header: ASCII "1\n0 0 0\n" (format 4)
  // or "1 0 0 0\n", and "1 1\n" or "1 15 0 1\n"; binary, a tag and three doubles, two indices
  const double node_bytes = !binary ? 8.0 : v4 ? 8.0 + 24.0 : 4.0 + 24.0;
  const double element_bytes = !binary ? (v4 ? 4.0 : 8.0) : v4 ? 16.0 : 8.0;
  double claimed[2] = {0, 0};
  const char* sections[2] = {"$Nodes", "$Elements"};
  const char* what[2] = {"nodes", "elements"};
  const double least[2] = {node_bytes, element_bytes};
  for (int k = 0; k < 2; ++k) {
    while (in.line(line) && line != sections[k]) {
    }
    // where the counts are: their line, or in format 4's binary headers their byte
    const std::string at = binary && v4 ? "at byte " + std::to_string(in.offset()) : "line " + std::to_string(in.line_number());
    double n = 0;
    if (!count(n)) break;  // no such section, or cut short: Gmsh says so
    const double after = static_cast<double>(size) - static_cast<double>(in.offset());
    if (n * least[k] > after) {
      char msg[400];
      std::snprintf(msg, sizeof msg,
                    ": its %s header claims %.0f %s, but the %.0f bytes after it hold at most %.0f (each takes at "
                    "least %.0f bytes): the header does not describe this file (damaged or cut short)",
                    sections[k], n, what[k], std::max(after, 0.0), std::floor(std::max(after, 0.0) / least[k]), least[k]);
      return fail(error, who + " " + at + msg);
    }
    claimed[k] = n;
  }
  const double need = claimed[0] * kMshBytesPerNode + claimed[1] * kMshBytesPerElement;
  if (memory_limit > 0 && need > memory_limit) {
    char msg[300];
    std::snprintf(msg, sizeof msg, ": its headers claim %.0f nodes and %.0f elements; reading them would need about %s, more than the %s",
                  claimed[0], claimed[1], input_bytes_words(need).c_str(), input_bytes_words(memory_limit).c_str());
    return fail(error, who + msg + " " + kMemoryLimitBound);
  }
  return true;
}

std::string signal_words(int sig) {
  const char* name = sigdescr_np(sig);
  return std::string(name ? name : "signal") + " (signal " + std::to_string(sig) + ")";
}

}  // namespace

bool gmsh_reads(const std::string& path) {
  const std::string e = lower_extension(path);
  return e == ".msh" || gmsh_is_geometry(path);
}

bool gmsh_is_geometry(const std::string& path) {
  const std::string e = lower_extension(path);
  return e == ".step" || e == ".stp" || e == ".iges" || e == ".igs" || e == ".brep" || e == ".brp" || e == ".geo";
}

bool read_with_gmsh(const GmshMeshRequest& r, ImportedSurface& out, std::string* error) {
  const std::string who = "mesh file '" + r.path + "'";
  std::error_code ec;
  if (!fs::exists(r.path, ec)) return fail(error, who + " does not exist");
  if (fs::is_directory(r.path, ec)) return fail(error, who + " is a directory, not a mesh file");
  // a regular file within the memory limit, before a process is started for it; a .msh file's
  // header claims checked against its size and the memory limit before Gmsh allocates for them
  const std::uintmax_t bound = r.memory_limit_bytes > 0 ? static_cast<std::uintmax_t>(r.memory_limit_bytes) : 0;
  if (const std::string problem = input_file_problem(r.path, bound, kMemoryLimitBound); !problem.empty())
    return fail(error, who + " " + problem);
  if (!r.mesh_geometry && !check_msh_claims(r.path, who, r.memory_limit_bytes, error)) return false;
  const pid_t parent = getpid();
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return fail(error, "cannot start Gmsh for " + who + ": no pipe");
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]), close(fds[1]);
    return fail(error, "cannot start Gmsh for " + who + ": fork failed");
  }
  if (pid == 0) {
    close(fds[0]);
    child_main(fds[1], r, parent);
  }
  close(fds[1]);
  std::string bytes;
  const auto start = std::chrono::steady_clock::now();
  std::string stopped;
  const double byte_limit = r.memory_limit_bytes > 0 ? r.memory_limit_bytes : 8e9;
  char buffer[1 << 16];
  while (true) {
    pollfd p{fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, 100);
    if (ready > 0) {
      const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      bytes.append(buffer, static_cast<std::size_t>(n));
      if (static_cast<double>(bytes.size()) > byte_limit) {
        stopped = "its mesh exceeds the memory this machine allows";
        break;
      }
    } else if (ready < 0 && errno != EINTR) {
      break;
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (r.stop && r.stop->load()) {
      stopped = "stopped by a signal while Gmsh was working";
      break;
    }
    if (elapsed > r.time_limit_seconds) {
      stopped = "Gmsh did not finish within " + std::to_string(static_cast<int>(r.time_limit_seconds)) +
                " s (part.mesh_time_limit); a smaller part.mesh_size makes more elements and takes longer";
      break;
    }
  }
  close(fds[0]);
  if (!stopped.empty()) kill(pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!stopped.empty()) return fail(error, who + ": " + stopped);
  if (WIFSIGNALED(status))
    return fail(error, who + ": Gmsh crashed on it (" + signal_words(WTERMSIG(status)) +
                           "); the file may be malformed, or Gmsh cannot mesh this geometry");
  Reader in{bytes};
  const std::uint8_t ok = in.get<std::uint8_t>();
  // the child always answers before it exits: no answer is a crash that a handler turned into an
  // exit status (a sanitizer's, or a library's own)
  if (!in.ok)
    return fail(error, who + ": Gmsh crashed on it (it ended with exit status " + std::to_string(WEXITSTATUS(status)) +
                           " and no answer); the file may be malformed, or Gmsh cannot mesh this geometry");
  if (!ok) return fail(error, who + ": " + in.get_string());

  ImportedSurface s;
  s.file = fs::path(r.path).filename().string();
  const std::string ext = lower_extension(r.path);
  s.format = !r.mesh_geometry ? "Gmsh MSH"
             : ext == ".geo"   ? "Gmsh .geo script"
             : ext == ".step" || ext == ".stp" ? "STEP part"
             : ext == ".iges" || ext == ".igs" ? "IGES part"
                                               : "BREP part";
  const std::vector<double> xyz = in.get_array<double>();
  const std::vector<std::int32_t> elem_nodes = in.get_array<std::int32_t>();
  const std::vector<std::int32_t> elem_entity = in.get_array<std::int32_t>();
  const std::vector<std::int64_t> elem_tag = in.get_array<std::int64_t>();
  const std::vector<double> normals = in.get_array<double>();
  if (!in.ok || xyz.size() % 3 != 0 || elem_nodes.size() != 4 * elem_entity.size() || elem_tag.size() != elem_entity.size() ||
      (!normals.empty() && normals.size() != 12 * elem_tag.size()))
    return fail(error, who + ": Gmsh's answer was cut short");
  for (std::size_t k = 0; k < xyz.size(); k += 3) s.points.emplace_back(xyz[k], xyz[k + 1], xyz[k + 2]);
  for (std::size_t e = 0; e < elem_entity.size(); ++e) {
    ImportedElement el;
    for (int a = 0; a < 4; ++a) el.nodes[a] = elem_nodes[4 * e + a];
    el.entity = elem_entity[e];
    el.where = "element " + std::to_string(elem_tag[e]) + " (surface " + std::to_string(elem_entity[e]) + ")";
    s.elements.push_back(std::move(el));
    if (!normals.empty()) {
      std::array<Eigen::Vector3d, 4> n;
      for (int a = 0; a < 4; ++a) n[a] = Eigen::Vector3d(normals[12 * e + 3 * a], normals[12 * e + 3 * a + 1], normals[12 * e + 3 * a + 2]);
      s.corner_normals.push_back(n);
    }
  }
  const std::uint64_t groups = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; in.ok && k < groups; ++k) {
    ImportedGroup grp;
    grp.name = in.get_string();
    grp.dimension = in.get<std::int32_t>();
    grp.origin = in.get_string() + " in " + s.file;
    const auto nodes = in.get_array<std::int32_t>();
    const auto elements = in.get_array<std::int32_t>();
    const auto segments = in.get_array<std::int32_t>();
    grp.nodes.assign(nodes.begin(), nodes.end());
    grp.elements.assign(elements.begin(), elements.end());
    for (std::size_t i = 0; i + 1 < segments.size(); i += 2) grp.segments.push_back({segments[i], segments[i + 1]});
    s.groups.push_back(std::move(grp));
  }
  const std::uint64_t notes = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; in.ok && k < notes; ++k) s.notes.push_back(in.get_string());
  if (!in.ok) return fail(error, who + ": Gmsh's answer was cut short");
  out = std::move(s);
  return true;
}

}  // namespace ff::io
