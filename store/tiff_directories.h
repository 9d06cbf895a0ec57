// The directories (pages) of a TIFF file, walked without decoding anything: how many pages there are, and
// whether each directory and the image data it points to lie inside the file. OpenImageIO takes a file cut
// short for one with fewer pages, and reads image data past the end as zeros without failing; this walk
// tells a cut file from a whole one. Classic and BigTIFF, either byte order. Plain file reads, no
// OpenImageIO.
//
// Threads: any; no shared state.
#pragma once

#include <optional>
#include <string>

namespace ropecast {

// The number of pages of a TIFF file (0 when its header points to no directory), or nullopt when `path` does
// not start with a TIFF header. Throws ropecast::Error naming the file and page when a directory or the image
// data of a page lies past the end of the file, or when the directories loop. The caller has checked that
// `path` is a regular file.
std::optional<int> tiffPageCount(const std::string& path);

}  // namespace ropecast
