#pragma once
/// Damaging an HDF5 file on purpose, for the results.h5 integrity tests: where a row of a
/// chunked data set and the checksum of an object header lie in the file, and overwriting
/// bytes there. Uses the HDF5 C API (tests only; app/io keeps HDF5 out of public headers).
#include <hdf5.h>

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ff::test {

/// File offset of row `row` (along dimension 0) of the chunked data set `dset`. A chunk
/// without compression is stored as its rows in order (with Fletcher32, followed by 4 checksum
/// bytes), so the row sits at chunk address + (row - chunk's first row) * row bytes.
inline std::uint64_t chunk_row_offset(const std::string& path, const std::string& dset, hsize_t row) {
  std::uint64_t offset = 0;
  bool found = false;
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = f < 0 ? -1 : H5Dopen2(f, dset.c_str(), H5P_DEFAULT);
  if (d >= 0) {
    const hid_t space = H5Dget_space(d), type = H5Dget_type(d), dcpl = H5Dget_create_plist(d);
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(rank), chunk(rank), origin(rank);
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    std::uint64_t row_bytes = H5Tget_size(type);
    for (int k = 1; k < rank; ++k) row_bytes *= dims[k];
    if (H5Pget_layout(dcpl) == H5D_CHUNKED && H5Pget_chunk(dcpl, rank, chunk.data()) == rank) {
      hsize_t chunks = 0;
      H5Dget_num_chunks(d, space, &chunks);  // 1.10 wants a real data space, not H5S_ALL
      for (hsize_t c = 0; c < chunks && !found; ++c) {
        unsigned mask = 0;
        haddr_t addr = 0;
        hsize_t size = 0;
        if (H5Dget_chunk_info(d, space, c, origin.data(), &mask, &addr, &size) < 0) break;
        if (origin[0] <= row && row < origin[0] + chunk[0]) {
          offset = addr + (row - origin[0]) * row_bytes;
          found = true;
        }
      }
    }
    H5Pclose(dcpl);
    H5Tclose(type);
    H5Sclose(space);
    H5Dclose(d);
  }
  if (f >= 0) H5Fclose(f);
  if (!found) throw std::runtime_error("no chunk holds row " + std::to_string(row) + " of " + dset + " in " + path);
  return offset;
}

/// File offset of the 4-byte checksum that ends the first chunk of the version-2 object
/// header of `object` (a group that tracks attribute creation order has one; version-1 headers
/// carry no checksum). Layout from the HDF5 file format specification, "Version 2 Object
/// Header": "OHDR", version, flags, [times: 16 bytes if flags & 0x20], [attribute phase change:
/// 4 bytes if flags & 0x10], size of chunk 0 (1 << (flags & 3) bytes), chunk 0, checksum.
inline std::uint64_t object_header_checksum_offset(const std::string& path, const std::string& object) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw std::runtime_error("cannot open " + path);
  haddr_t addr = HADDR_UNDEF;
#if H5_VERSION_GE(1, 12, 0)
  H5O_info2_t info;
  if (H5Oget_info_by_name3(f, object.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0)
    H5VLnative_token_to_addr(f, info.token, &addr);
#else
  H5O_info_t info;
  if (H5Oget_info_by_name2(f, object.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0) addr = info.addr;
#endif
  H5Fclose(f);
  if (addr == HADDR_UNDEF) throw std::runtime_error("no object " + object + " in " + path);
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(addr));
  unsigned char head[32] = {0};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  if (std::string(reinterpret_cast<char*>(head), 4) != "OHDR")
    throw std::runtime_error(object + " in " + path + " has no version-2 object header");
  const unsigned flags = head[5];
  std::size_t at = 6 + ((flags & 0x20) ? 16 : 0) + ((flags & 0x10) ? 4 : 0);
  const std::size_t width = std::size_t{1} << (flags & 3);
  std::uint64_t size0 = 0;
  for (std::size_t k = 0; k < width; ++k) size0 |= std::uint64_t{head[at + k]} << (8 * k);
  return addr + at + width + size0;
}

/// Overwrites bytes of `path` at `offset` with `bytes`.
inline void overwrite(const std::string& path, std::uint64_t offset, const std::vector<unsigned char>& bytes) {
  std::fstream io(path, std::ios::binary | std::ios::in | std::ios::out);
  io.seekp(static_cast<std::streamoff>(offset));
  io.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!io) throw std::runtime_error("cannot overwrite " + path);
}

/// The bytes of `path` at `offset`.
inline std::vector<unsigned char> read_bytes(const std::string& path, std::uint64_t offset, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  std::vector<unsigned char> out(count);
  in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(count));
  out.resize(static_cast<std::size_t>(in.gcount()));
  return out;
}

}  // namespace ff::test
