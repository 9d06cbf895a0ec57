#include "tests/store/testutil_dicom.h"

#include <gdcmAttribute.h>
#include <gdcmFile.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmUIDGenerator.h>
#include <gdcmWriter.h>

#include <cstring>
#include <stdexcept>

namespace ropecast::testing {
namespace {

template <uint16_t Group, uint16_t Element, typename T>
void put(gdcm::DataSet& ds, const T& value) {
  gdcm::Attribute<Group, Element> attribute;
  attribute.SetValue(value);
  ds.Replace(attribute.GetAsDataElement());
}

// A sequence of `items` under `tag`.
gdcm::DataElement sequenceOf(const gdcm::Tag& tag, const std::vector<gdcm::DataSet>& items) {
  gdcm::SmartPointer<gdcm::SequenceOfItems> sequence = new gdcm::SequenceOfItems();
  sequence->SetLengthToUndefined();
  for (const gdcm::DataSet& nested : items) {
    gdcm::Item item;
    item.SetVLToUndefined();
    item.SetNestedDataSet(nested);
    sequence->AddItem(item);
  }
  gdcm::DataElement element(tag);
  element.SetVR(gdcm::VR::SQ);
  element.SetValue(*sequence);
  element.SetVLToUndefined();
  return element;
}

// An Enhanced CT image's functional groups (DicomSliceSpec::framePositions).
void putFunctionalGroups(gdcm::DataSet& ds, const DicomSliceSpec& spec) {
  gdcm::DataSet measures, orientation, rescale, shared;
  if (spec.pixelSpacing) {
    gdcm::Attribute<0x0028, 0x0030> spacing = {{spec.pixelSpacing->x, spec.pixelSpacing->y}};
    measures.Replace(spacing.GetAsDataElement());
  }
  put<0x0018, 0x0050>(measures, 1.0);  // Slice Thickness, unlike the positions' spacing
  shared.Replace(sequenceOf(gdcm::Tag(0x0028, 0x9110), {measures}));
  if (spec.orientation) {
    gdcm::Attribute<0x0020, 0x0037> value;
    for (unsigned i = 0; i < 6; ++i) value.SetValue((*spec.orientation)[i], i);
    orientation.Replace(value.GetAsDataElement());
    shared.Replace(sequenceOf(gdcm::Tag(0x0020, 0x9116), {orientation}));
  }
  put<0x0028, 0x1053>(rescale, spec.slope.value_or(1.0));
  put<0x0028, 0x1052>(rescale, spec.intercept.value_or(0.0));
  put<0x0028, 0x1054>(rescale, "HU");
  shared.Replace(sequenceOf(gdcm::Tag(0x0028, 0x9145), {rescale}));
  ds.Replace(sequenceOf(gdcm::Tag(0x5200, 0x9229), {shared}));

  std::vector<gdcm::DataSet> frames;
  for (const glm::dvec3& p : spec.framePositions) {
    gdcm::DataSet position, frame;
    gdcm::Attribute<0x0020, 0x0032> value = {{p.x, p.y, p.z}};
    position.Replace(value.GetAsDataElement());
    frame.Replace(sequenceOf(gdcm::Tag(0x0020, 0x9113), {position}));
    frames.push_back(frame);
  }
  ds.Replace(sequenceOf(gdcm::Tag(0x5200, 0x9230), frames));
}

// The writer's own file is filled: gdcm::File is reference-counted, and a writer given one frees it.
void write(const std::string& path, gdcm::Writer& writer) {
  writer.GetFile().GetHeader().SetDataSetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  writer.SetFileName(path.c_str());
  if (!writer.Write()) throw std::runtime_error("GDCM could not write " + path);
}

}  // namespace

void writeDicomSlice(const std::string& path, const DicomSliceSpec& spec) {
  gdcm::Writer writer;
  gdcm::DataSet& ds = writer.GetFile().GetDataSet();
  gdcm::UIDGenerator uids;
  const bool enhanced = !spec.framePositions.empty();
  put<0x0008, 0x0016>(ds, enhanced ? "1.2.840.10008.5.1.4.1.1.2.1"  // Enhanced CT Image Storage
                                   : "1.2.840.10008.5.1.4.1.1.2");  // CT Image Storage
  put<0x0008, 0x0018>(ds, uids.Generate());
  put<0x0020, 0x000d>(ds, "1.2.826.0.1.3680043.9.7607.0");
  put<0x0020, 0x000e>(ds, spec.seriesUid.c_str());
  put<0x0008, 0x0060>(ds, spec.modality.c_str());
  if (!spec.seriesDescription.empty()) put<0x0008, 0x103e>(ds, spec.seriesDescription.c_str());
  if (spec.instance) put<0x0020, 0x0013>(ds, *spec.instance);
  if (spec.temporalPosition) put<0x0020, 0x0100>(ds, *spec.temporalPosition);
  if (enhanced) putFunctionalGroups(ds, spec);
  if (spec.position && !enhanced) {
    gdcm::Attribute<0x0020, 0x0032> position = {{spec.position->x, spec.position->y, spec.position->z}};
    ds.Replace(position.GetAsDataElement());
  }
  if (spec.orientation && !enhanced) {
    gdcm::Attribute<0x0020, 0x0037> orientation;
    for (unsigned i = 0; i < 6; ++i) orientation.SetValue((*spec.orientation)[i], i);
    ds.Replace(orientation.GetAsDataElement());
  }
  if (spec.pixelSpacing && !enhanced) {
    gdcm::Attribute<0x0028, 0x0030> spacing = {{spec.pixelSpacing->x, spec.pixelSpacing->y}};
    ds.Replace(spacing.GetAsDataElement());
  }
  if (spec.slope && !enhanced) put<0x0028, 0x1053>(ds, *spec.slope);
  if (spec.intercept && !enhanced) put<0x0028, 0x1052>(ds, *spec.intercept);
  if (spec.frames) put<0x0028, 0x0008>(ds, int32_t(*spec.frames));
  if (spec.spacingBetweenSlices) put<0x0018, 0x0088>(ds, *spec.spacingBetweenSlices);
  put<0x0028, 0x0002>(ds, spec.samplesPerPixel);
  put<0x0028, 0x0004>(ds, spec.photometric.c_str());
  put<0x0028, 0x0010>(ds, uint16_t(spec.rows));
  put<0x0028, 0x0011>(ds, uint16_t(spec.columns));
  put<0x0028, 0x0100>(ds, spec.bitsAllocated);
  put<0x0028, 0x0101>(ds, spec.bitsStored);
  put<0x0028, 0x0102>(ds, uint16_t(spec.bitsStored - 1));
  put<0x0028, 0x0103>(ds, uint16_t(spec.isSigned ? 1 : 0));
  if (spec.samplesPerPixel > 1) put<0x0028, 0x0006>(ds, uint16_t(0));

  const size_t samples = size_t(spec.rows) * spec.columns * spec.samplesPerPixel * spec.frames.value_or(1);
  const size_t bytesPerSample = spec.bitsAllocated / 8;
  std::vector<char> bytes(spec.pixelDataBytes ? spec.pixelDataBytes : (samples * bytesPerSample + 1) / 2 * 2,
                          0);  // even length, as DICOM requires
  for (size_t i = 0; i < samples && i < spec.stored.size() && (i + 1) * bytesPerSample <= bytes.size(); ++i) {
    // Two's complement within the allocated bits: the bits above Bits Stored copy the sign, as writers do.
    const uint64_t raw = uint64_t(spec.stored[i]);
    std::memcpy(bytes.data() + i * bytesPerSample, &raw, bytesPerSample);  // little-endian host
  }
  gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
  pixels.SetVR(spec.bitsAllocated == 8 ? gdcm::VR::OB : gdcm::VR::OW);
  pixels.SetByteValue(bytes.data(), uint32_t(bytes.size()));
  ds.Replace(pixels);
  write(path, writer);
}

void writeDicomWithoutImage(const std::string& path) {
  gdcm::Writer writer;
  gdcm::DataSet& ds = writer.GetFile().GetDataSet();
  gdcm::UIDGenerator uids;
  put<0x0008, 0x0016>(ds, "1.2.840.10008.5.1.4.1.1.88.11");  // Basic Text SR Storage
  put<0x0008, 0x0018>(ds, uids.Generate());
  put<0x0008, 0x0060>(ds, "SR");
  put<0x0020, 0x000e>(ds, "1.2.826.0.1.3680043.9.7607.99");
  write(path, writer);
}

}  // namespace ropecast::testing
