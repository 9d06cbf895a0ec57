// Which inputs are HDF5 files, and which of a file's datasets an input names: FILE, or FILE:/GROUP/DATASET
// (the path inside the file after the first colon that ends an existing file's name). Recognized without the
// HDF5 library (the executable decides before it loads its image module, where HDF5 is read).
// Pure functions over the file system; any thread.
#pragma once

#include <optional>
#include <string>

namespace ropecast {

struct Hdf5Spec {
  std::string file;
  std::string dataset;  // the path inside the file; empty: the source chooses (store/source_hdf5.h)
};

// The extensions taken for HDF5 without looking inside: .h5, .hdf5, .he5, .hdf, .ims (Imaris), .nc
// (netCDF-4).
bool hasHdf5Extension(const std::string& path);
// Whether the file at `path` begins with the HDF5 format signature (a file with a user block elsewhere is
// recognized by its extension).
bool startsWithHdf5Signature(const std::string& path);

// `spec` as an HDF5 input: a regular file with an HDF5 extension or signature, alone or followed by ":" and a
// dataset path; nullopt for anything else (which the other sources, or "no such file", answer).
std::optional<Hdf5Spec> hdf5SpecOf(const std::string& spec);

}  // namespace ropecast
