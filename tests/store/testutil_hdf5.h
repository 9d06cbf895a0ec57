// Writes HDF5 files for the HDF5 source's tests (tests/store/source_hdf5_test.cpp) and tests/cli/hdf5.sh's
// writer: datasets of any type, byte order, rank, chunking and compression, in groups made as needed, and
// the attributes ilastik, Fiji and Imaris write. Test code only; one thread; failures throw
// std::runtime_error.
#pragma once

#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace ropecast::testing {

// A file created (truncated) at `path`, closed at the end of the scope.
class Hdf5Writer {
 public:
  explicit Hdf5Writer(const std::string& path)
      : file_(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT)) {
    if (file_ < 0) throw std::runtime_error("test: cannot create the HDF5 file " + path);
  }
  ~Hdf5Writer() {
    for (hid_t d : opened_) H5Dclose(d);
    for (hid_t g : openedGroups_) H5Gclose(g);
    if (links_ >= 0) H5Pclose(links_);
    H5Fclose(file_);
  }
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  struct Dataset {
    std::string path;             // "/group/name"
    std::vector<hsize_t> extent;  // HDF5's order: the last axis varies fastest
    hid_t fileType = H5T_STD_U8LE;
    hid_t memoryType = H5T_NATIVE_UINT8;
    const void* values = nullptr;  // extent's product of memoryType
    std::vector<hsize_t> chunk;    // empty: contiguous
    bool compressed = false;       // shuffle and deflate (chunked only)
  };

  // Writes the dataset; returns it open (closed with the file), for attributes.
  hid_t write(const Dataset& d) {
    const hid_t space = H5Screate_simple(int(d.extent.size()), d.extent.data(), nullptr);
    const hid_t create = H5Pcreate(H5P_DATASET_CREATE);
    if (!d.chunk.empty()) {
      H5Pset_chunk(create, int(d.chunk.size()), d.chunk.data());
      if (d.compressed) {
        H5Pset_shuffle(create);
        H5Pset_deflate(create, 6);
      }
    }
    const hid_t dataset =
        H5Dcreate2(file_, d.path.c_str(), d.fileType, space, linksWithGroups(), create, H5P_DEFAULT);
    H5Pclose(create);
    H5Sclose(space);
    if (dataset < 0 || H5Dwrite(dataset, d.memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.values) < 0)
      throw std::runtime_error("test: cannot write the HDF5 dataset " + d.path);
    opened_.push_back(dataset);
    return dataset;
  }

  // A group at `path` (and those above it); returned open, for attributes.
  hid_t group(const std::string& path) {
    const hid_t g = H5Gcreate2(file_, path.c_str(), linksWithGroups(), H5P_DEFAULT, H5P_DEFAULT);
    if (g < 0) throw std::runtime_error("test: cannot create the HDF5 group " + path);
    openedGroups_.push_back(g);
    return g;
  }

  // A dataset of fixed-length strings, which is no volume.
  void writeText(const std::string& path, const std::string& text) {
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, text.size());
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t dataset =
        H5Dcreate2(file_, path.c_str(), type, space, linksWithGroups(), H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data());
    H5Dclose(dataset);
    H5Sclose(space);
    H5Tclose(type);
  }

  hid_t file() const { return file_; }

 private:
  hid_t linksWithGroups() {
    if (links_ < 0) {
      links_ = H5Pcreate(H5P_LINK_CREATE);
      H5Pset_create_intermediate_group(links_, 1);
    }
    return links_;
  }

  hid_t file_;
  hid_t links_ = -1;
  std::vector<hid_t> opened_, openedGroups_;
};

// Numbers as an attribute of `object` (ilastik's and Fiji's `element_size_um`).
inline void writeNumbersAttribute(hid_t object, const std::string& name, const std::vector<double>& values) {
  const hsize_t count = values.size();
  const hid_t space = H5Screate_simple(1, &count, nullptr);
  const hid_t attribute = H5Acreate2(object, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attribute, H5T_NATIVE_DOUBLE, values.data());
  H5Aclose(attribute);
  H5Sclose(space);
}

// Text as Imaris writes its attributes: an array of single characters.
inline void writeCharsAttribute(hid_t object, const std::string& name, const std::string& text) {
  const hsize_t count = text.size();
  const hid_t space = H5Screate_simple(1, &count, nullptr);
  const hid_t attribute = H5Acreate2(object, name.c_str(), H5T_C_S1, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attribute, H5T_C_S1, text.data());
  H5Aclose(attribute);
  H5Sclose(space);
}

}  // namespace ropecast::testing
