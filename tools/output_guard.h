// OutputGuard: the check every command that writes files makes before it writes anything, so that no typo
// replaces an input (a scan, a store) with an output, and no two outputs of one command land on one file.
// A command lists what it reads and what it will write, each with the option that names it, and calls
// check(), which throws ropecast::Error naming both options (or the one output that names a folder). Owned
// by the command; main thread.
//
// Two paths are the same file when stat() finds the same device and inode (through symlinks and hard links);
// for paths that do not exist yet, when their absolute paths are equal with the symlinks of their existing
// folders resolved. A volume input that is a directory counts as itself and every entry in it, and a glob
// pattern as every file it matches; any other input counts as the path itself.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace ropecast::tools {

class OutputGuard {
 public:
  // `who` starts every message ("render", "convert").
  explicit OutputGuard(std::string who) : who_(std::move(who)) {}

  // A file the command reads (a store, --tf, the suite). `what` names it in messages: "the input", "--tf",
  // "the suite". A folder given for it is not expanded: the command's reader refuses it, in its own words.
  // Empty paths and procedural:NAME:SIZE specs are ignored.
  void addInput(std::string what, const std::string& path);
  // A volume `ropecast convert` reads (volumeSpecFiles): a raw, NRRD, MetaImage or NIfTI file and the data
  // file its header names, a DICOM image and the other DICOM files of its folder, or a folder or glob pattern
  // of slices and every file in it; DICOM files in the folders below (listDicomFilesBelow) count too.
  void addVolumeInput(std::string what, const std::string& spec);
  // A file the command will write. `option` names it in messages ("-o", "--stats").
  void addOutput(std::string option, const std::string& path);
  // Files of a series the command may write into `directory` (e.g. --every's OUT_NNNN.png), given by a test
  // of the file name; `pattern` shows them in messages ("out_NNNN.png").
  void addOutputSeries(std::string option, const std::string& directory, std::string pattern,
                       std::function<bool(const std::string& fileName)> nameMatches);

  // Throws ropecast::Error when an output (or an existing name of a series) is a folder, or the same file as
  // an input or as another output.
  void check() const;
  // What check() would throw, in words ("" when every output is its own new file).
  std::string problem() const;

 private:
  struct Named {
    std::string name;  // the option or input it came from
    std::string path;
  };
  struct Series {
    std::string option, directory, pattern;
    std::function<bool(const std::string&)> nameMatches;
  };
  std::string who_;
  std::vector<Named> inputs_, outputs_;
  std::vector<Series> series_;
};

// A key equal for two paths exactly when OutputGuard takes them for one file (the same device and inode, or,
// not yet written, the same absolute name with the existing folders' links resolved).
std::string fileIdentity(const std::string& path);

// The input files named by a volume spec as `ropecast convert` reads it (store/volume_source.h): nothing for
// procedural:NAME:SIZE, a raw, TIFF or HDF5 file itself (FILE:/DATASET its file), a Zarr or N5 folder and
// every file below it, an NRRD, MetaImage or NIfTI
// header and its detached data file (and a NIfTI image its header), a DICOM image and the DICOM files of its
// folder (its series is among them), a directory or glob pattern as given (addVolumeInput expands them); for
// a directory or a DICOM file, the DICOM files of the folders below (a disc's series).
std::vector<std::string> volumeSpecFiles(const std::string& spec);

}  // namespace ropecast::tools
