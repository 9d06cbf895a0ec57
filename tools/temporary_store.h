// A volume given where a store is read (render, view, bench modes, regress): converted as `ropecast convert`
// converts it (with the options that say how to read it: tools/volume_read_options.h), with a progress line,
// into a store under the system's temporary folder, which is opened and at once unlinked: the open store
// keeps its bytes, and they go when the process ends, however it ends (the commands remove the converter's
// temporary file on a signal: core/temporary_file.h). Any thread (regress converts its cases' volumes side by
// side).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "store/store.h"
#include "store/volume_source.h"

namespace ropecast::tools {

// `input` as openVolumeSource reads it with `options`, bricked by `brick` (default kDefaultBrickSize). `who`
// names the command in messages ("render"); `quiet` drops the line that says what is done and the progress
// line. Throws ropecast::Error as openVolumeSource and the converter do.
std::unique_ptr<Store> openVolumeAsStore(const std::string& input, const SourceOptions& options,
                                         std::optional<uint32_t> brick, bool quiet, const std::string& who);

}  // namespace ropecast::tools
