// Which files make an image stack and in which order (store/source_images.h reads them): file names and
// folder listings only, no image library, so every build has them. Any thread.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace ropecast {

// Whether `path` names a slice image by its extension: .tif, .tiff or .png, in any case.
bool isSliceImageName(const std::string& path);

// Name order in which slices are stacked: runs of digits compare as numbers, so "s2.png" < "s10.png" (and
// zero-padded names keep their plain order).
bool sliceNameLess(std::string_view a, std::string_view b);

// The slice files of a directory (its .tif/.tiff/.png files, case-insensitive) or of a glob pattern, in
// sliceNameLess order. Throws ropecast::Error naming the directory or pattern if nothing matches.
std::vector<std::string> listSliceFiles(const std::string& directoryOrPattern);

// For files numbered in their names (the last run of digits): a note when numbers repeat or some are missing
// between the first and the last (slices are stacked one after another whatever their numbers); else "".
std::string sliceNumberingNote(const std::vector<std::string>& files);

}  // namespace ropecast
