// The DICOM-series VolumeSource, read with GDCM: the single-frame images of one series (CT, MR, PET, ...) in
// one folder, whatever their file names. Slices are stacked by their position along the slice normal (Image
// Position (Patient) on the normal of Image Orientation (Patient)), or by Instance Number where positions are
// missing; never by name. Spacing: Pixel Spacing in-plane (its second value along x, the rows' direction),
// the distance between neighbouring positions across; --spacing overrides both. Values: the stored ones
// through Rescale Slope and Intercept (Hounsfield units for CT), kept exact as an integer type where every
// slope and intercept is an integer, else float32. Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time). The listing functions, any thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "store/volume_source.h"

namespace ropecast {

// Whether the file holds the DICOM part-10 signature ("DICM" after a 128-byte preamble). False for files that
// cannot be read.
bool startsWithDicomMagic(const std::string& path);

// The DICOM files (startsWithDicomMagic) directly inside `directory`, in name order; empty when it has none.
// Throws ropecast::Error naming the directory if it cannot be listed.
std::vector<std::string> listDicomFiles(const std::string& directory);

// How many folders deep listDicomFilesBelow looks, and how many entries it looks at before it gives up: a
// disc's or an export's layout (a DICOMDIR beside DICOM/patient/study/series folders) is four folders deep.
inline constexpr int kDicomSearchDepth = 5;
inline constexpr size_t kDicomSearchEntries = 200000;

// The DICOM files in the subfolders of `directory` (not in it), down to kDicomSearchDepth folders, in name
// order; symbolic links to folders are not followed. Throws ropecast::Error naming the directory if it
// cannot be listed, or if it holds more than kDicomSearchEntries entries there (not a series' export).
std::vector<std::string> listDicomFilesBelow(const std::string& directory);

// A DICOM series: `spec` is a folder that holds the images of one series (other DICOM objects, a DICOMDIR
// say, and files of other kinds are passed over), or one image of a series, whose folder's images of that
// series are read. A folder without images of its own (a disc's or an export's top, or its DICOMDIR given)
// is searched below (listDicomFilesBelow): its one series is read, wherever its images lie. Every image's
// header is checked when opening: a folder of several series (the error lists them, each with one of its
// files to give instead), a multi-frame image among others, color images, images of different sizes, pixel
// formats or orientations, two images at one position, or a file cut short (dicomStructureProblem) throw
// ropecast::Error naming the files. Slices that lie off a regular stack (a tilted gantry, a missing
// slice) are resampled where they lie (store/placed_stack.h), noted, unless options.spacing is given. A
// series of one multi-frame image (enhanced CT or MR, NM) is a volume of its frames, decoded whole when
// opening (GDCM decodes pixel data at once): an enhanced image's frames placed by its functional groups
// (Plane Position) are stacked as a series' slices are (two at one position refused), other frames in the
// file's order; frames that say no spacing between them (a cine) are stacked at the pixel spacing, noted.
std::unique_ptr<VolumeSource> openDicomSource(const std::string& spec, const SourceOptions& options);

}  // namespace ropecast
