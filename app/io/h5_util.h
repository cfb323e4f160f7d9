#pragma once
/// \file h5_util.h
/// Private helpers over the HDF5 C API for the result store: owned identifiers, error
/// capture (the HDF5 error stack turned into one sentence), and typed attribute/data set
/// access. Only app/io/*.cpp include this file.

#include <hdf5.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace ff::io::h5 {

/// An HDF5 call failed; what() is "<what we tried>: <HDF5 reason>".
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
  /// The HDF5 reason alone, when fail() threw it ("" otherwise). Kept here because closing
  /// handles while the exception unwinds clears HDF5's error stack.
  std::string reason;
  /// reason, or what() when there is none
  std::string reason_or_what() const { return reason.empty() ? what() : reason; }
};

/// The most specific entry of this thread's HDF5 error stack as one line, "" if empty.
std::string error_reason();

/// Throws Failure(what + ": " + error_reason()).
[[noreturn]] void fail(const std::string& what);

inline hid_t check_id(hid_t id, const std::string& what) {
  if (id < 0) fail(what);
  return id;
}
inline void check(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

/// Turns off HDF5's automatic error printing on this thread while alive (errors are reported
/// through our messages instead), restoring the previous handler afterwards. The first Quiet
/// also arranges for printing to be off when the library shuts down at exit: HDF5 1.10 leaks
/// internal free-list blocks when it meets a corrupt metadata checksum, and its shutdown then
/// prints "HDF5: infinite loop closing library" after our own message.
class Quiet {
 public:
  Quiet();
  ~Quiet();
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

 private:
  H5E_auto2_t old_func_ = nullptr;
  void* old_data_ = nullptr;
};

/// Owns one HDF5 identifier (file, group, data set, attribute, space, type, property list)
/// and releases it with H5Idec_ref. Never wrap predefined identifiers such as
/// H5T_NATIVE_DOUBLE.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset() {
    if (id_ >= 0) H5Idec_ref(id_);
    id_ = H5I_INVALID_HID;
  }
  /// Gives up ownership.
  hid_t release() {
    hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

/// Variable-length UTF-8 string type (h5py reads attributes of this type as str).
Handle vlen_string_type();
/// Enum {FALSE = 0, TRUE = 1} over int8: h5py reads it as numpy bool, h5dump as FALSE/TRUE.
Handle bool_type();

// links
bool has_link(hid_t loc, const std::string& name);
/// Group with object times off; with `track_order`, attribute creation order is kept.
Handle create_group(hid_t loc, const std::string& name, bool track_order);
Handle open_group(hid_t loc, const std::string& name);
Handle open_dataset(hid_t loc, const std::string& name);

// attributes (written attributes are overwritten in place, keeping their creation order)
bool has_attr(hid_t obj, const std::string& name);
void write_attr_string(hid_t obj, const std::string& name, const std::string& value);
void write_attr_strings(hid_t obj, const std::string& name, const std::vector<std::string>& values);
void write_attr_double(hid_t obj, const std::string& name, double value);
void write_attr_int64(hid_t obj, const std::string& name, std::int64_t value);
void write_attr_doubles(hid_t obj, const std::string& name, const std::vector<double>& values);
std::vector<double> read_attr_doubles(hid_t obj, const std::string& name);
std::string read_attr_string(hid_t obj, const std::string& name);
std::vector<std::string> read_attr_strings(hid_t obj, const std::string& name);
double read_attr_double(hid_t obj, const std::string& name);
std::int64_t read_attr_int64(hid_t obj, const std::string& name);
/// Attribute names in creation order when the object tracks it, else in name order.
std::vector<std::string> attr_names(hid_t obj);

// data sets
/// Fixed-size data set of shape `dims` filled from `data` (may be empty): chunked with the
/// Fletcher32 checksum filter so that damaged bytes fail to read (an empty one stays contiguous).
void write_fixed_dataset(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                         const std::vector<hsize_t>& dims, const void* data);
/// Scalar variable-length UTF-8 string data set with attribute `checksum` (FNV-1a 64 of its
/// bytes): variable-length data lives in the global heap, where no HDF5 filter reaches.
void write_string_dataset(hid_t loc, const std::string& name, const std::string& text);
/// Throws Failure when the text does not match its `checksum` (files without one are trusted).
std::string read_string_dataset(hid_t loc, const std::string& name);
std::vector<hsize_t> dataset_dims(hid_t dset);
/// Reads rows [first, first + count) along dimension 0 into `out` (count * row elements).
void read_rows(hid_t dset, hid_t mem_type, hsize_t first, hsize_t count, void* out,
               const std::string& what);

}  // namespace ff::io::h5
