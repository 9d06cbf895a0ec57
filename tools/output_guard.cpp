#include "tools/output_guard.h"

#include <glob.h>
#include <sys/stat.h>

#include <filesystem>
#include <optional>

#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "core/temporary_file.h"
#include "store/bdv_xml.h"
#include "store/hdf5_spec.h"
#include "store/procedural.h"
#include "store/source_dicom.h"
#include "store/source_metaimage.h"
#include "store/source_n5.h"
#include "store/source_nifti.h"
#include "store/source_nrrd.h"
#include "store/source_zarr.h"
#include "store/volume_source.h"

namespace ropecast::tools {
namespace {

namespace fs = std::filesystem;

struct FileId {
  dev_t device;
  ino_t inode;
  bool operator==(const FileId&) const = default;
};

// stat() follows symlinks, so a link and its target share the id, as do hard links.
std::optional<FileId> fileIdOf(const std::string& path) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return std::nullopt;
  return FileId{s.st_dev, s.st_ino};
}

// For a path that does not exist yet: absolute, lexically normal, with the symlinks of the folders that
// exist resolved ("out/../a.png" and "a.png" are one file to be).
std::string futureName(const std::string& path) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal().string() : canonical.string();
}

bool sameFile(const std::string& a, const std::string& b) {
  const std::optional<FileId> idA = fileIdOf(a), idB = fileIdOf(b);
  if (idA && idB) return *idA == *idB;
  if (idA || idB) return false;  // one exists, the other is still to be written
  return futureName(a) == futureName(b);
}

// The files an input stands for: a directory and its entries, a pattern's matches, or the path itself.
std::vector<std::string> expandInput(const std::string& path) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    files.push_back(path);
    for (const auto& entry : fs::directory_iterator(path, ec)) files.push_back(entry.path().string());
    return files;
  }
  if (isSlicePattern(path)) {
    glob_t matches{};
    if (::glob(path.c_str(), 0, nullptr, &matches) == 0)
      for (size_t i = 0; i < matches.gl_pathc; ++i) files.push_back(matches.gl_pathv[i]);
    globfree(&matches);
    return files;
  }
  files.push_back(path);
  return files;
}

// `subject` is the output as the user named it ("-o a.png", "--every out_NNNN.png would write out_0003.png").
std::string sameFileMessage(const std::string& who, const std::string& subject, const std::string& path,
                            const std::string& otherName, const std::string& otherPath, bool otherIsInput) {
  const std::string link = path == otherPath ? "" : " (through a link or another name)";
  if (otherIsInput)
    return who + ": " + subject + ": the same file as " + otherName + " " + otherPath + link +
           "; refusing to overwrite an input, nothing was written";
  return who + ": " + subject + " and " + otherName + " " + otherPath + " are the same file" + link +
         ": give each output its own file; nothing was written";
}

}  // namespace

std::string fileIdentity(const std::string& path) {
  if (const std::optional<FileId> id = fileIdOf(path))
    return "id:" + std::to_string(id->device) + ":" + std::to_string(id->inode);
  return "name:" + futureName(path);
}

void OutputGuard::addInput(std::string what, const std::string& path) {
  if (!path.empty() && !isProceduralSpec(path)) inputs_.push_back({std::move(what), path});
}

void OutputGuard::addVolumeInput(std::string what, const std::string& spec) {
  for (const std::string& given : volumeSpecFiles(spec))
    for (std::string& file : expandInput(given)) inputs_.push_back({what, std::move(file)});
}

void OutputGuard::addOutput(std::string option, const std::string& path) {
  if (!path.empty()) outputs_.push_back({std::move(option), path});
}

void OutputGuard::addOutputSeries(std::string option, const std::string& directory, std::string pattern,
                                  std::function<bool(const std::string&)> nameMatches) {
  series_.push_back(
      {std::move(option), directory.empty() ? "." : directory, std::move(pattern), std::move(nameMatches)});
}

std::string OutputGuard::problem() const {
  for (size_t o = 0; o < outputs_.size(); ++o) {
    const Named& out = outputs_[o];
    std::error_code ec;
    if (fs::is_directory(out.path, ec))
      return who_ + ": " + out.name + " " + out.path + ": a folder; expected the name of a file to write, " +
             "nothing was written";
    if (const std::string why = outputFileProblem(out.path); !why.empty())
      return who_ + ": " + out.name + " " + out.path + ": " + why + "; nothing was written";
    for (const Named& in : inputs_)
      if (sameFile(out.path, in.path))
        return sameFileMessage(who_, out.name + " " + out.path, out.path, in.name, in.path, true);
    for (size_t p = 0; p < o; ++p)
      if (sameFile(out.path, outputs_[p].path))
        return sameFileMessage(who_, outputs_[p].name + " " + outputs_[p].path, outputs_[p].path, out.name,
                               out.path, false);
  }
  for (const Series& series : series_) {
    const std::string option = series.option + " " + (fs::path(series.directory) / series.pattern).string();
    // Existing files of the series (found by listing its folder) against inputs and outputs.
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(series.directory, ec)) {
      if (!series.nameMatches(entry.path().filename().string())) continue;
      const std::string path = entry.path().string();
      if (entry.is_directory(ec))
        return who_ + ": " + option + " would write " + path +
               ": a folder has that name; nothing was written";
      for (const Named& in : inputs_)
        if (sameFile(path, in.path))
          return sameFileMessage(who_, option + " would write " + path, path, in.name, in.path, true);
      for (const Named& out : outputs_)
        if (sameFile(path, out.path))
          return sameFileMessage(who_, option + " would write " + path, path, out.name, out.path, false);
    }
    // Outputs still to be written that would be a file of the series.
    for (const Named& out : outputs_) {
      const fs::path future = futureName(out.path);
      if (futureName(series.directory) == future.parent_path().string() &&
          series.nameMatches(future.filename().string()))
        return sameFileMessage(who_, option + " would write " + out.path, out.path, out.name, out.path,
                               false);
    }
  }
  return "";
}

void OutputGuard::check() const {
  if (const std::string message = problem(); !message.empty()) throw Error(message);
}

std::vector<std::string> volumeSpecFiles(const std::string& spec) {
  if (isProceduralSpec(spec)) return {};
  if (const std::optional<Hdf5Spec> hdf5 = hdf5SpecOf(spec)) return {hdf5->file};
  // A Zarr or N5 folder: its metadata and chunk files, at any depth ("/"-separated keys nest them, N5's
  // blocks lie a folder per axis deep).
  if (isZarrFolder(spec) || isN5Folder(spec)) {
    std::vector<std::string> files{spec};
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(spec, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
      if (it->is_regular_file(ec)) files.push_back(it->path().string());
    return files;
  }
  std::vector<std::string> files{spec};
  std::error_code ec;
  const bool folderGiven = fs::is_directory(spec, ec);
  if (folderGiven || startsWithDicomMagic(spec)) {
    const std::string parent = fs::path(spec).parent_path().string();
    const std::string folder = folderGiven ? spec : parent.empty() ? "." : parent;
    // A folder counts with its entries (addVolumeInput expands it), a DICOM image with its folder's DICOM
    // files; both with the DICOM files of the folders below, where a disc's or an export's series lie.
    if (!folderGiven)
      for (std::string& file : listDicomFiles(folder)) files.push_back(std::move(file));
    try {
      for (std::string& file : listDicomFilesBelow(folder)) files.push_back(std::move(file));
    } catch (const Error&) {  // a folder too large to search is refused when the source opens
    }
    return files;
  }
  // A detached header names its data file; a header that cannot be read is refused when the source opens.
  const std::string ext = lowerExtension(spec);
  try {
    if (ext == ".nhdr" || ext == ".nrrd") {
      const NrrdHeader header = readNrrdHeaderFile(spec);
      if (!header.dataFile.empty()) files.push_back(nrrdDataPath(header, spec));
    } else if (ext == ".mhd" || ext == ".mha") {
      const MetaImageHeader header = readMetaImageHeaderFile(spec);
      if (!header.dataFile.empty() || !header.sliceFiles.empty())
        for (std::string& data : metaImageDataPaths(header, spec)) files.push_back(std::move(data));
    } else if (const std::string pairHeader = niftiPairHeader(spec); !pairHeader.empty()) {
      files.push_back(pairHeader);  // an .img given for its pair
    } else if (hasNiftiName(spec)) {
      const std::string data = niftiDataPath(readNiftiHeaderFile(spec), spec);
      if (!data.empty() && data != spec) files.push_back(data);
    } else if (ext == ".xml" && isBdvXml(spec)) {  // a BigDataViewer dataset: the XML, its HDF5 file or N5
      const BdvDataset dataset = parseBdvXml(readTextInput(spec, "BigDataViewer XML " + spec), spec);
      if (dataset.format == BdvImageFormat::N5) {
        for (std::string& file : volumeSpecFiles(dataset.images)) files.push_back(std::move(file));
      } else {
        files.push_back(dataset.images);
      }
    }
  } catch (const Error&) {
  }
  return files;
}

}  // namespace ropecast::tools
