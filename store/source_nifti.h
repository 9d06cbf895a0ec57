// The NIfTI VolumeSource (neuroimaging: FSL, SPM, FreeSurfer, ITK-SNAP, 3D Slicer): NIfTI-1 and NIfTI-2,
// single files (.nii, and .nii.gz compressed whole) and header/image pairs (.hdr with .img, either
// gzip-compressed). Samples are read through FileSamples (store/file_samples.h); values scaled by
// scl_slope and scl_inter are delivered scaled, in the narrowest integer type that holds them exactly where
// slope and intercept are whole numbers, else as float. Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time: a compressed stream is per-source state).
#pragma once

#include <memory>
#include <string>

#include "store/nifti_header.h"
#include "store/volume_source.h"

namespace ropecast {

// Whether `path` is named as a NIfTI file: .nii, .nii.gz, .hdr or .hdr.gz, in any case (an .img names its
// pair's image; see niftiPairHeader).
bool hasNiftiName(const std::string& path);
// For an .img or .img.gz, the header beside it (.hdr or .hdr.gz) when one exists; "" otherwise.
std::string niftiPairHeader(const std::string& imagePath);

// The header of the NIfTI file at `path` (a regular file, gzip-compressed or not). Throws ropecast::Error
// naming the file.
NiftiHeader readNiftiHeaderFile(const std::string& path);
// The file holding the samples of the header read from `headerPath`: the header's own file, or for a pair
// the .img (or .img.gz) beside it; "" when a pair's image is missing.
std::string niftiDataPath(const NiftiHeader& header, const std::string& headerPath);

// `path` is a .nii, .nii.gz, .hdr or .hdr.gz (or an .img whose header is beside it). Spacing from options
// overrides the header's. Throws ropecast::Error naming the file and the problem: malformed header (see
// parseNiftiHeader), missing image file, data shorter than the header says (uncompressed at once, compressed
// as it is read).
std::unique_ptr<VolumeSource> openNiftiSource(const std::string& path, const SourceOptions& options);

}  // namespace ropecast
