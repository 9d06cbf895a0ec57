// The options that say how to read a volume: --dims, --type, --byte-order and --header-bytes of a raw file,
// --spacing of any volume, --time and --channel of a file of several volumes, --axes of an HDF5 dataset, a
// Zarr array or an N5 dataset that does not name its axes. `convert` and `info` take them,
// and so do render, view and bench modes for a volume given where a store is read (tools/temporary_store.h).
// Main thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/sample_type.h"
#include "store/volume_source.h"

namespace ropecast::tools {

struct VolumeReadArgs {
  std::vector<uint32_t> dims;  // --dims X,Y,Z; empty: not given
  std::optional<SampleType> type;
  std::optional<ByteOrder> byteOrder;
  std::optional<uint64_t> headerBytes;
  std::vector<double> spacing;                 // --spacing SX,SY,SZ; empty: not given
  std::optional<uint32_t> timePoint, channel;  // --time T, --channel C
  std::string axes;                            // --axes LETTERS; empty: not given

  // The first option given ("--dims", ...), or "" when none was.
  std::string firstGiven() const;
};

// Adds the eight options, with their help.
void addVolumeReadOptions(CLI::App& app, VolumeReadArgs& a);

// The SourceOptions of the arguments. Throws UsageError naming `who` ("convert") for a spacing out of range
// or
// --axes letters that are not axes.
SourceOptions sourceOptionsOf(const VolumeReadArgs& a, const std::string& who);

// For an input that is not read as a volume: throws UsageError naming the first option given, the input and
// `why` ("the store s.rcast keeps what it was converted with").
void refuseVolumeReadOptions(const VolumeReadArgs& a, const std::string& why);

}  // namespace ropecast::tools
