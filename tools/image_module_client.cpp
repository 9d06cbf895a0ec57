// The executable's side of the image module (tools/image_module.h): loading ropecast_images.so on first use,
// and the functions the executable would otherwise link from OpenImageIO's parts of reference/, store/ and
// tools/, as calls into the module's table.
#include <dlfcn.h>

#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "store/source_dicom.h"
#include "store/source_hdf5.h"
#include "store/source_images.h"
#include "tools/image_module.h"

namespace ropecast::tools {
namespace {

namespace fs = std::filesystem;

const ImageModule& loadImageModule() {
  std::error_code ec;
  const fs::path executable = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("cannot find ropecast's image module: /proc/self/exe: " + ec.message());
  const fs::path candidates[] = {
      executable.parent_path() / kImageModuleFile,
      (executable.parent_path() / ROPECAST_IMAGE_MODULE_DIR / kImageModuleFile).lexically_normal()};
  const fs::path* found = nullptr;
  for (const fs::path& candidate : candidates)
    if (!found && fs::is_regular_file(candidate, ec)) found = &candidate;
  const std::string need =
      "image files other than PNG (EXR, TIFF), image stacks, DICOM and HDF5 need ropecast's image module ";
  if (!found)
    throw Error(need + kImageModuleFile + ", which is neither at " + candidates[0].string() + " nor at " +
                candidates[1].string() + " (install it with ropecast, or rebuild)");
  void* handle = ::dlopen(found->c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw Error(need + found->string() + ", which does not load: " + ::dlerror());
  using Entry = const ImageModule* (*)();
  const auto entry = reinterpret_cast<Entry>(::dlsym(handle, kImageModuleEntry));
  const ImageModule* module = entry ? entry() : nullptr;
  if (!module || module->layout != ImageModule::kLayout || module->size != sizeof(ImageModule))
    throw Error(need + found->string() +
                ", which is from another build of ropecast (rebuild or reinstall both)");
  return *module;  // never unloaded: sources and images it made may live to the end of the process
}

}  // namespace

const ImageModule& imageModule() {
  // A static's initialization that throws is tried again by the next call, which then says why again.
  static const ImageModule& module = loadImageModule();
  return module;
}

}  // namespace ropecast::tools

namespace ropecast {

std::vector<unsigned char> encodeImage(const std::string& where, const std::string& path,
                                       const ImageEncoding& encoding, const void* pixels) {
  return tools::imageModule().encodeImage(where, path, encoding, pixels);
}

std::string imageWriterProblem(const std::string& path) {
  try {
    return tools::imageModule().imageWriterProblem(path);
  } catch (const Error& e) {  // a problem with the output, in the words of its contract (the viewer asks)
    return e.what();
  }
}

FloatImage decodeImage(const std::string& path) {
  return tools::imageModule().decodeImage(path);
}

int countImagePages(const std::string& path) {
  return tools::imageModule().countImagePages(path);
}

std::unique_ptr<VolumeSource> openImageStackSource(const std::string& directoryOrPattern,
                                                   const SourceOptions& options) {
  return tools::imageModule().openImageStackSource(directoryOrPattern, options);
}

std::unique_ptr<VolumeSource> openMultiPageTiffSource(const std::string& path, const SourceOptions& options) {
  return tools::imageModule().openMultiPageTiffSource(path, options);
}

std::unique_ptr<VolumeSource> openDicomSource(const std::string& spec, const SourceOptions& options) {
  return tools::imageModule().openDicomSource(spec, options);
}

std::unique_ptr<VolumeSource> openHdf5Source(const std::string& spec, const SourceOptions& options) {
  return tools::imageModule().openHdf5Source(spec, options);
}

}  // namespace ropecast
