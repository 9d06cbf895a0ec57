// The image-stack VolumeSource, read with OpenImageIO: a directory of 2D slices (every .tif/.tiff/.png file),
// a glob pattern of slices (e.g. "dir/slice_*.png"), or one multi-page TIFF (each page a slice). Slices are
// single-channel int8, uint8, int16, uint16, int32, uint32, float32 or float64 images (PNG holds uint8 and
// uint16 only), or gray+alpha, RGB or RGBA ones (palette images too) read as gray from the first channel
// where R = G = B and alpha is opaque at every pixel (checked as each slice is read), all of one size, type
// and bit depth (unsigned samples of fewer bits than their type, a 12-bit TIFF or a 1-bit PNG say, keep the
// file's values, and so do MinIsWhite TIFFs, whose 0 viewers show as white); slice 0 is z = 0. TIFFs whose
// samples OpenImageIO would read as zeros are refused (tiled ones of 24- or 64-bit samples, and those of
// 64-bit samples one row high). Owned by loader/.
//
// Threads: as VolumeSource (readSlab from one thread at a time).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "store/slice_files.h"
#include "store/volume_source.h"

namespace ropecast {

// How many subimages (pages) an image file has. Throws ropecast::Error naming the file if it cannot be read,
// and the page where a TIFF is cut short.
int countImagePages(const std::string& path);

// A stack of slice files (a directory or glob pattern). Every slice is checked when opening: a slice of
// different size, type, bit depth or photometric interpretation (MinIsWhite among MinIsBlack), an unreadable
// file, a multi-channel image, or a TIFF whose samples OpenImageIO would read as zeros throws ropecast::Error
// naming the file.
std::unique_ptr<VolumeSource> openImageStackSource(const std::string& directoryOrPattern,
                                                   const SourceOptions& options);

// A multi-page TIFF, one slice per page, checked as above (errors name the file and page; a file cut short is
// refused, not read as fewer pages or zeros).
std::unique_ptr<VolumeSource> openMultiPageTiffSource(const std::string& path, const SourceOptions& options);

}  // namespace ropecast
