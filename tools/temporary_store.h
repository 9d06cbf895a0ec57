// A volume given where a store is read (render, view, bench modes, regress): converted as `ropecast convert`
// converts it (with the options that say how to read it: tools/volume_read_options.h), with a progress line,
// into a store under the system's temporary folder, which is opened and at once unlinked: the open store
// keeps its bytes, and they go when the process ends, however it ends (the commands remove the converter's
// temporary file on a signal: core/temporary_file.h). Any thread (regress converts its cases' volumes side by
// side; the viewer converts a series' time points on a thread of their own).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "store/store.h"
#include "store/volume_source.h"

namespace ropecast::tools {

// How openVolumeAsStore tells what it does.
struct ConversionReport {
  bool quiet = false;  // no line saying what is done, no progress line
  bool notes = true;   // the source's notes, as warnings
  // Where given, in place of the progress line: the fraction of the volume converted, after each slab, on the
  // converting thread. It may throw to stop the conversion, which then leaves nothing behind.
  std::function<void(double)> progress;
};

// `input` as openVolumeSource reads it with `options`, bricked by `brick` (default kDefaultBrickSize). `who`
// names the command in messages ("render"). `volume`, where given, receives what the source read (its time
// points and channels among it). Throws ropecast::Error as openVolumeSource and the converter do.
std::unique_ptr<Store> openVolumeAsStore(const std::string& input, const SourceOptions& options,
                                         std::optional<uint32_t> brick, const ConversionReport& report,
                                         const std::string& who, VolumeInfo* volume = nullptr);

}  // namespace ropecast::tools
