#include "app/io/h5_util.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "app/io/frame_checksum.h"

namespace ff::io::h5 {

namespace {

struct Deepest {
  bool found = false;
  std::string desc;
  hid_t min_num = -1;
};

// the walk goes upward: entry 0 is where the library first detected the error
herr_t take_deepest(unsigned n, const H5E_error2_t* err, void* data) {
  auto* d = static_cast<Deepest*>(data);
  if (!d->found) {
    d->found = true;
    d->desc = err->desc ? err->desc : "";
    d->min_num = err->min_num;
  }
  return 0;
}

std::size_t element_count(hid_t space) {
  hssize_t n = H5Sget_simple_extent_npoints(space);
  return n < 0 ? 0 : static_cast<std::size_t>(n);
}

Handle scalar_space() { return Handle(check_id(H5Screate(H5S_SCALAR), "create scalar space")); }

Handle simple_space(const std::vector<hsize_t>& dims) {
  return Handle(check_id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                         "create data space"));
}

// creates the attribute, or reuses an existing one of the same type class and size so that
// rewriting (outcome, frames_written) keeps creation order and does not grow the header
Handle attr_for_write(hid_t obj, const std::string& name, hid_t file_type, hid_t space) {
  if (has_attr(obj, name)) {
    Handle a(check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute '" + name + "'"));
    Handle t(check_id(H5Aget_type(a.get()), "type of attribute '" + name + "'"));
    Handle s(check_id(H5Aget_space(a.get()), "space of attribute '" + name + "'"));
    bool same_class = H5Tget_class(t.get()) == H5Tget_class(file_type);
    bool same_vlen = H5Tget_class(t.get()) != H5T_STRING ||
                     H5Tis_variable_str(t.get()) == H5Tis_variable_str(file_type);
    bool same_shape = H5Sget_simple_extent_type(s.get()) == H5Sget_simple_extent_type(space) &&
                      element_count(s.get()) == element_count(space);
    if (same_class && same_vlen && same_shape) return a;
    a.reset();
    check(H5Adelete(obj, name.c_str()), "replace attribute '" + name + "'");
  }
  return Handle(check_id(H5Acreate2(obj, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT),
                         "create attribute '" + name + "'"));
}

Handle open_attr(hid_t obj, const std::string& name) {
  return Handle(check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute '" + name + "'"));
}

// reads n strings stored with string type `stored` (variable or fixed length)
std::vector<std::string> read_strings(hid_t stored, std::size_t n, const std::string& what,
                                      herr_t (*read)(hid_t mem_type, void* buf, void* ctx),
                                      void* ctx) {
  std::vector<std::string> out;
  if (H5Tget_class(stored) != H5T_STRING) throw Failure(what + ": not a string");
  if (n == 0) return out;
  if (H5Tis_variable_str(stored) > 0) {
    Handle mem = vlen_string_type();
    std::vector<char*> buf(n, nullptr);
    check(read(mem.get(), buf.data(), ctx), what);
    for (char* p : buf) {
      out.emplace_back(p ? p : "");
      if (p) H5free_memory(p);
    }
  } else {
    std::size_t size = H5Tget_size(stored);
    Handle mem(check_id(H5Tcopy(H5T_C_S1), what));
    check(H5Tset_size(mem.get(), size), what);
    std::vector<char> buf(n * size + 1, '\0');
    check(read(mem.get(), buf.data(), ctx), what);
    for (std::size_t i = 0; i < n; ++i) {
      const char* p = buf.data() + i * size;
      out.emplace_back(p, strnlen(p, size));
    }
  }
  return out;
}

herr_t read_attr_cb(hid_t mem_type, void* buf, void* ctx) {
  return H5Aread(*static_cast<hid_t*>(ctx), mem_type, buf);
}

herr_t read_dset_cb(hid_t mem_type, void* buf, void* ctx) {
  return H5Dread(*static_cast<hid_t*>(ctx), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
}

herr_t collect_name(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

}  // namespace

std::string error_reason() {
  Deepest d;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take_deepest, &d);
  if (!d.found) return "unknown HDF5 error";
  // system errors arrive as "..., errno = 2, error message = 'No such file or directory', ...":
  // the quoted system message is the reason a user needs
  const std::string key = "error message = '";
  if (auto at = d.desc.find(key); at != std::string::npos) {
    auto end = d.desc.find('\'', at + key.size());
    if (end != std::string::npos) {
      std::string head = d.desc.substr(0, d.desc.find_first_of(":,"));
      std::string reason = head + ": " + d.desc.substr(at + key.size(), end - at - key.size());
      if (head.find("lock") != std::string::npos) {
        reason += " (another process has the file open for writing; is a run still going?)";
      }
      return reason;
    }
  }
  std::string reason = d.desc;
  char minor[256] = {0};
  if (d.min_num >= 0 && H5Eget_msg(d.min_num, nullptr, minor, sizeof(minor)) > 0) {
    std::string m = minor;
    for (char& c : m) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!m.empty() && reason.find(m) == std::string::npos) {
      reason += reason.empty() ? m : " (" + m + ")";
    }
  }
  return reason;
}

void fail(const std::string& what) {
  const std::string reason = error_reason();
  Failure f(what.empty() ? reason : what + ": " + reason);
  f.reason = reason;
  throw f;
}

Quiet::Quiet() {
  H5Eget_auto2(H5E_DEFAULT, &old_func_, &old_data_);  // initialises the library if needed
  // registered after HDF5's own atexit hook, so it runs first; the leak itself is HDF5's
  // (inside H5Gopen2/H5Dopen2 of a damaged object header) and the OS reclaims it at exit
  static const bool quiet_shutdown =
      std::atexit([] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }) == 0;
  (void)quiet_shutdown;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Quiet::~Quiet() { H5Eset_auto2(H5E_DEFAULT, old_func_, old_data_); }

Handle vlen_string_type() {
  Handle t(check_id(H5Tcopy(H5T_C_S1), "create string type"));
  check(H5Tset_size(t.get(), H5T_VARIABLE), "create string type");
  check(H5Tset_cset(t.get(), H5T_CSET_UTF8), "create string type");
  return t;
}

Handle bool_type() {
  Handle t(check_id(H5Tenum_create(H5T_NATIVE_INT8), "create bool type"));
  std::int8_t no = 0, yes = 1;
  check(H5Tenum_insert(t.get(), "FALSE", &no), "create bool type");
  check(H5Tenum_insert(t.get(), "TRUE", &yes), "create bool type");
  return t;
}

bool has_link(hid_t loc, const std::string& name) {
  return H5Lexists(loc, name.c_str(), H5P_DEFAULT) > 0;
}

Handle create_group(hid_t loc, const std::string& name, bool track_order) {
  Handle gcpl(check_id(H5Pcreate(H5P_GROUP_CREATE), "create group '" + name + "'"));
  check(H5Pset_obj_track_times(gcpl.get(), 0), "create group '" + name + "'");
  if (track_order) {
    check(H5Pset_attr_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED),
          "create group '" + name + "'");
  }
  return Handle(check_id(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT),
                         "create group '" + name + "'"));
}

Handle open_group(hid_t loc, const std::string& name) {
  return Handle(check_id(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), "open group '" + name + "'"));
}

Handle open_dataset(hid_t loc, const std::string& name) {
  return Handle(
      check_id(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), "open data set '" + name + "'"));
}

bool has_attr(hid_t obj, const std::string& name) { return H5Aexists(obj, name.c_str()) > 0; }

void write_attr_string(hid_t obj, const std::string& name, const std::string& value) {
  Handle type = vlen_string_type();
  Handle space = scalar_space();
  Handle a = attr_for_write(obj, name, type.get(), space.get());
  const char* p = value.c_str();
  check(H5Awrite(a.get(), type.get(), &p), "write attribute '" + name + "'");
}

void write_attr_strings(hid_t obj, const std::string& name,
                        const std::vector<std::string>& values) {
  Handle type = vlen_string_type();
  Handle space = simple_space({values.size()});
  Handle a = attr_for_write(obj, name, type.get(), space.get());
  std::vector<const char*> ptrs;
  for (const auto& v : values) ptrs.push_back(v.c_str());
  if (!ptrs.empty()) check(H5Awrite(a.get(), type.get(), ptrs.data()), "write attribute '" + name + "'");
}

void write_attr_double(hid_t obj, const std::string& name, double value) {
  Handle space = scalar_space();
  Handle a = attr_for_write(obj, name, H5T_IEEE_F64LE, space.get());
  check(H5Awrite(a.get(), H5T_NATIVE_DOUBLE, &value), "write attribute '" + name + "'");
}

void write_attr_doubles(hid_t obj, const std::string& name, const std::vector<double>& values) {
  Handle space = simple_space({values.size()});
  Handle a = attr_for_write(obj, name, H5T_IEEE_F64LE, space.get());
  if (!values.empty()) check(H5Awrite(a.get(), H5T_NATIVE_DOUBLE, values.data()), "write attribute '" + name + "'");
}

std::vector<double> read_attr_doubles(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  Handle s(check_id(H5Aget_space(a.get()), "read attribute '" + name + "'"));
  std::vector<double> v(element_count(s.get()));
  if (!v.empty()) check(H5Aread(a.get(), H5T_NATIVE_DOUBLE, v.data()), "read attribute '" + name + "'");
  return v;
}

void write_attr_int64(hid_t obj, const std::string& name, std::int64_t value) {
  Handle space = scalar_space();
  Handle a = attr_for_write(obj, name, H5T_STD_I64LE, space.get());
  check(H5Awrite(a.get(), H5T_NATIVE_INT64, &value), "write attribute '" + name + "'");
}

std::string read_attr_string(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  Handle t(check_id(H5Aget_type(a.get()), "read attribute '" + name + "'"));
  Handle s(check_id(H5Aget_space(a.get()), "read attribute '" + name + "'"));
  if (element_count(s.get()) != 1) throw Failure("attribute '" + name + "' is not a single string");
  hid_t id = a.get();
  return read_strings(t.get(), 1, "read attribute '" + name + "'", read_attr_cb, &id).at(0);
}

std::vector<std::string> read_attr_strings(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  Handle t(check_id(H5Aget_type(a.get()), "read attribute '" + name + "'"));
  Handle s(check_id(H5Aget_space(a.get()), "read attribute '" + name + "'"));
  hid_t id = a.get();
  return read_strings(t.get(), element_count(s.get()), "read attribute '" + name + "'",
                      read_attr_cb, &id);
}

double read_attr_double(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  double v = 0.0;
  check(H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v), "read attribute '" + name + "'");
  return v;
}

std::int64_t read_attr_int64(hid_t obj, const std::string& name) {
  Handle a = open_attr(obj, name);
  std::int64_t v = 0;
  check(H5Aread(a.get(), H5T_NATIVE_INT64, &v), "read attribute '" + name + "'");
  return v;
}

std::vector<std::string> attr_names(hid_t obj) {
  std::vector<std::string> names;
  hsize_t idx = 0;
  if (H5Aiterate2(obj, H5_INDEX_CRT_ORDER, H5_ITER_INC, &idx, collect_name, &names) >= 0) {
    return names;
  }
  names.clear();
  idx = 0;
  check(H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_name, &names),
        "list attributes");
  return names;
}

void write_fixed_dataset(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                         const std::vector<hsize_t>& dims, const void* data) {
  const std::string what = "create data set '" + name + "'";
  Handle space = simple_space(dims);
  Handle dcpl(check_id(H5Pcreate(H5P_DATASET_CREATE), what));
  check(H5Pset_obj_track_times(dcpl.get(), 0), what);
  const bool empty = element_count(space.get()) == 0;
  if (!empty) {  // chunks of about 1 MiB along the first dimension, each with its checksum
    std::vector<hsize_t> chunk = dims;
    std::size_t row_bytes = H5Tget_size(file_type);
    for (std::size_t k = 1; k < dims.size(); ++k) row_bytes *= static_cast<std::size_t>(dims[k]);
    chunk[0] = std::clamp<hsize_t>((1u << 20) / std::max<std::size_t>(row_bytes, 1), 1, dims[0]);
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), what);
    check(H5Pset_fletcher32(dcpl.get()), what);
  }
  Handle d(check_id(H5Dcreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(),
                               H5P_DEFAULT),
                    what));
  if (!empty) {
    check(H5Dwrite(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "write data set '" + name + "'");
  }
}

void write_string_dataset(hid_t loc, const std::string& name, const std::string& text) {
  Handle type = vlen_string_type();
  Handle space = scalar_space();
  Handle dcpl(check_id(H5Pcreate(H5P_DATASET_CREATE), "create data set '" + name + "'"));
  check(H5Pset_obj_track_times(dcpl.get(), 0), "create data set '" + name + "'");
  Handle d(check_id(H5Dcreate2(loc, name.c_str(), type.get(), space.get(), H5P_DEFAULT,
                               dcpl.get(), H5P_DEFAULT),
                    "create data set '" + name + "'"));
  const char* p = text.c_str();
  check(H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p),
        "write data set '" + name + "'");
  const std::uint64_t sum = fnv1a(kFnvOffset, p, std::strlen(p));  // what is stored: up to a NUL
  Handle a = attr_for_write(d.get(), "checksum", H5T_STD_U64LE, space.get());
  check(H5Awrite(a.get(), H5T_NATIVE_UINT64, &sum), "write attribute 'checksum' of '" + name + "'");
}

std::string read_string_dataset(hid_t loc, const std::string& name) {
  Handle d = open_dataset(loc, name);
  Handle t(check_id(H5Dget_type(d.get()), "read data set '" + name + "'"));
  Handle s(check_id(H5Dget_space(d.get()), "read data set '" + name + "'"));
  if (element_count(s.get()) != 1) throw Failure("data set '" + name + "' is not a single string");
  hid_t id = d.get();
  std::string text = read_strings(t.get(), 1, "read data set '" + name + "'", read_dset_cb, &id).at(0);
  if (has_attr(d.get(), "checksum")) {
    Handle a = open_attr(d.get(), "checksum");
    std::uint64_t sum = 0;
    check(H5Aread(a.get(), H5T_NATIVE_UINT64, &sum), "read attribute 'checksum' of '" + name + "'");
    if (sum != fnv1a(kFnvOffset, text.data(), text.size())) {
      throw Failure("data set '" + name + "' is damaged: its text does not match its checksum attribute");
    }
  }
  return text;
}

std::vector<hsize_t> dataset_dims(hid_t dset) {
  Handle s(check_id(H5Dget_space(dset), "data set shape"));
  int rank = H5Sget_simple_extent_ndims(s.get());
  if (rank < 0) fail("data set shape");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0) check(H5Sget_simple_extent_dims(s.get(), dims.data(), nullptr), "data set shape");
  return dims;
}

void read_rows(hid_t dset, hid_t mem_type, hsize_t first, hsize_t count, void* out,
               const std::string& what) {
  Handle fspace(check_id(H5Dget_space(dset), what));
  int rank = H5Sget_simple_extent_ndims(fspace.get());
  if (rank < 1) throw Failure(what + ": data set has no frame dimension");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  check(H5Sget_simple_extent_dims(fspace.get(), dims.data(), nullptr), what);
  if (first + count > dims[0]) throw Failure(what + ": rows beyond the end of the data set");
  std::vector<hsize_t> start(dims.size(), 0), shape = dims;
  start[0] = first;
  shape[0] = count;
  for (hsize_t d : shape) {
    if (d == 0) return;  // nothing to read
  }
  check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr, shape.data(),
                            nullptr),
        what);
  Handle mspace = simple_space(shape);
  check(H5Dread(dset, mem_type, mspace.get(), fspace.get(), H5P_DEFAULT, out), what);
}

}  // namespace ff::io::h5
