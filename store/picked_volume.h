// Which of a file's several volumes a source reads: a NIfTI time series, a NRRD of dimension 4, a DICOM
// series of several time points, an ImageJ hyperstack or OME-TIFF of several channels, an Imaris file, an
// OME-Zarr image with time and channel axes, a MetaImage of several channels and a `.vti` array of several
// components hold one volume per time point and channel, and `--time T` and `--channel C` (SourceOptions,
// each counted from 0) pick one. Used by the file-format VolumeSources (store/) when they open. Functions:
// any thread; the sources: as VolumeSource says.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "store/volume_source.h"

namespace ropecast {

// How many volumes a file holds: its time points and channels (1 where it has no such axis).
struct VolumeCounts {
  uint64_t timePoints = 1, channels = 1;
  // What the file calls what --channel picks, for messages: "channel", or "view setup" (BigDataViewer's
  // channels, angles and tiles).
  std::string channelWord = "channel";
  // Each channel's name (BigDataViewer's view setups, OME's channels): said beside the channel's number where
  // every channel has one.
  std::vector<std::string> channelNames = {};
};

struct PickedVolume {
  uint32_t timePoint = 0, channel = 0;
  VolumeCounts counts;
  // For the source's description, where the file holds several volumes: " (time point 3 of 120)",
  // " (channel 1 of 2)", " (time point 0 of 5, channel 1 of 2)"; else "".
  std::string described;
  // A warning where the file holds several time points or channels and the options did not pick among them
  // (the first is read): what it holds and the option that picks another; else "".
  std::string note;
};

// The volume `options` pick of those `counts` says `file` ("NIfTI file a.nii") holds; the first time point
// and channel where an option is not given. Throws UsageError naming the option, the file and the range for
// an index that is not one of the file's (`--time 3` of a file of one volume included).
PickedVolume pickVolume(const SourceOptions& options, VolumeCounts counts, const std::string& file);

// Says in `info` which volume `picked` is: its counts and indices, its description followed by `described`,
// its note among the notes.
void describePicked(VolumeInfo& info, const PickedVolume& picked);

// The volume of one component of samples stored interleaved, `components` per point (a MetaImage's
// channels, a `.vti` array's components): `interleaved` reads them as a volume whose x axis holds components
// times `info.dims.x` samples; the source returned keeps those of `component` and is described by `info`. It
// reads every component's slices at most `maxStoredBytes` at a time (one slice at least); a slice of all
// components past 4 GiB is refused, naming `info.description`.
std::unique_ptr<VolumeSource> pickComponent(std::unique_ptr<VolumeSource> interleaved, uint32_t components,
                                            uint32_t component, VolumeInfo info,
                                            uint64_t maxStoredBytes = uint64_t(256) << 20);

// The volume `index` of volumes stored one after another (a NRRD's volumes along its last axis): `stacked`
// reads them as one volume of their slices, volume after volume; the source returned reads those of `index`
// and is described by `info`.
std::unique_ptr<VolumeSource> pickStacked(std::unique_ptr<VolumeSource> stacked, uint32_t index,
                                          VolumeInfo info);

}  // namespace ropecast
