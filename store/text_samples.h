// A volume's samples written as numbers in text, separated by blanks and line ends (legacy VTK's ASCII
// files), read as the VolumeSource of the file from the numbers' start: forward, a buffer at a time, starting
// over from the first number when a slab before the last one read is asked for (the converter reads in
// order). Used by the file-format sources (store/).
//
// Threads: as VolumeSource (one thread at a time per object).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "store/source_raw.h"
#include "store/volume_source.h"

namespace ropecast {

struct TextSamples {
  uint64_t start = 0;    // file offset of the first number
  std::string fileKind;  // how messages name the file: "legacy VTK file"
  // Each number times this is the sample (VTK writes unsigned chars of color scalars as fractions of 255);
  // integer types take it rounded to the nearest integer.
  double scale = 1.0;
};

// The VolumeSource whose samples are the numbers of `file` from `text.start` on, as `info` describes them.
// Sets the value range of uint8 volumes. A read throws ropecast::Error naming the file when it ends before
// the samples do, or when a number is not one, or not one of info.type (a fraction or an out-of-range value
// for an integer type), naming the sample.
std::unique_ptr<VolumeSource> openTextSampleSource(VolumeInfo info, std::unique_ptr<PosixFile> file,
                                                   TextSamples text);

}  // namespace ropecast
