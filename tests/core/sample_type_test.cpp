// Tests of the sample types: every type has its own name first and is found by it, no alias names two types
// (nor "char", whose signedness C leaves to the platform), the bytes per sample, the stored type, and the
// mapping of each type (exact for the integer types whose range fits 16 bits, quantized over [lo, hi]
// otherwise).
#include "core/sample_type.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace ropecast {
namespace {

constexpr SampleType kEveryType[] = {SampleType::Int8,    SampleType::UInt8,  SampleType::Int16,
                                     SampleType::UInt16,  SampleType::Int32,  SampleType::UInt32,
                                     SampleType::Float32, SampleType::Float64};

TEST(SampleType, EveryTypeIsFoundByItsOwnName) {
  const std::pair<SampleType, const char*> names[] = {
      {SampleType::Int8, "int8"},       {SampleType::UInt8, "uint8"},    {SampleType::Int16, "int16"},
      {SampleType::UInt16, "uint16"},   {SampleType::Int32, "int32"},    {SampleType::UInt32, "uint32"},
      {SampleType::Float32, "float32"}, {SampleType::Float64, "float64"}};
  for (const auto& [type, name] : names) {
    EXPECT_EQ(sampleTypeName(type), name);
    EXPECT_EQ(parseSampleType(name), type) << name;
  }
}

TEST(SampleType, NoNameStandsForTwoTypes) {
  std::set<std::string> seen;
  for (const auto& [name, type] : kSampleTypeNames) {
    EXPECT_TRUE(seen.insert(std::string(name)).second) << name << " is listed twice";
    EXPECT_EQ(parseSampleType(name), type) << name;
  }
  // "char" is signed on x86 and unsigned on ARM: the name does not say which (NRRD refuses it too).
  EXPECT_EQ(parseSampleType("char"), std::nullopt);
  EXPECT_EQ(parseSampleType("int64"), std::nullopt);
}

TEST(SampleType, TheAliasesOfTheWiderTypes) {
  const std::pair<const char*, SampleType> aliases[] = {
      {"i8", SampleType::Int8},           {"signed char", SampleType::Int8},
      {"int8_t", SampleType::Int8},       {"u32", SampleType::UInt32},
      {"uint", SampleType::UInt32},       {"unsigned int", SampleType::UInt32},
      {"uint32_t", SampleType::UInt32},   {"i32", SampleType::Int32},
      {"int", SampleType::Int32},         {"int32_t", SampleType::Int32},
      {"f64", SampleType::Float64},       {"double", SampleType::Float64},
      {"float64_t", SampleType::Float64}, {"Unsigned Int", SampleType::UInt32},
      {"DOUBLE", SampleType::Float64}};
  for (const auto& [name, type] : aliases) EXPECT_EQ(parseSampleType(name), type) << name;
}

TEST(SampleType, TheListInMessagesNamesEveryType) {
  const std::string list(kSampleTypeList);
  for (SampleType type : kEveryType)
    EXPECT_NE(list.find(sampleTypeName(type)), std::string::npos) << sampleTypeName(type);
}

TEST(SampleType, BytesAndStoredType) {
  EXPECT_EQ(bytesPerSample(SampleType::Int8), 1u);
  EXPECT_EQ(bytesPerSample(SampleType::UInt32), 4u);
  EXPECT_EQ(bytesPerSample(SampleType::Int32), 4u);
  EXPECT_EQ(bytesPerSample(SampleType::Float64), 8u);
  EXPECT_EQ(storedTypeFor(SampleType::Int8), SampleType::UInt8);
  EXPECT_EQ(storedTypeFor(SampleType::UInt8), SampleType::UInt8);
  for (SampleType type : {SampleType::Int16, SampleType::UInt16, SampleType::Int32, SampleType::UInt32,
                          SampleType::Float32, SampleType::Float64})
    EXPECT_EQ(storedTypeFor(type), SampleType::UInt16) << sampleTypeName(type);
}

TEST(SampleType, Int8IsStoredAsValuePlus128) {
  const ValueMapping m = valueMappingFor(SampleType::Int8, 0, 0);
  EXPECT_EQ(m.toData(0), -128.0);
  EXPECT_EQ(m.toData(255), 127.0);
}

TEST(SampleType, A32BitIntegerRangeThatFits16BitsIsKeptExactly) {
  for (SampleType type : {SampleType::Int32, SampleType::UInt32}) {
    const ValueMapping m = valueMappingFor(type, 1000000.0, 1065535.0);
    EXPECT_EQ(m.scale, 1.0) << sampleTypeName(type);
    EXPECT_EQ(m.offset, 1000000.0) << sampleTypeName(type);
    EXPECT_TRUE(mapsOverValueRange(type));
    EXPECT_TRUE(isExactMapping(type, m));
    const ValueMapping one = valueMappingFor(type, 7.0, 7.0);  // a constant volume: one stored value, 0
    EXPECT_EQ(one.scale, 1.0);
    EXPECT_EQ(one.toData(0), 7.0);
  }
}

TEST(SampleType, WiderRangesAndFloatsAreQuantizedOverTheRange) {
  for (SampleType type : {SampleType::Int32, SampleType::UInt32, SampleType::Float32, SampleType::Float64}) {
    const ValueMapping m = valueMappingFor(type, -10.0, 65536.0 - 10.0);
    EXPECT_DOUBLE_EQ(m.scale, 65536.0 / 65535.0) << sampleTypeName(type);
    EXPECT_EQ(m.toData(0), -10.0) << sampleTypeName(type);
    EXPECT_DOUBLE_EQ(m.toData(65535), 65536.0 - 10.0) << sampleTypeName(type);
    EXPECT_FALSE(isExactMapping(type, m)) << sampleTypeName(type);
  }
  EXPECT_FALSE(isExactMapping(SampleType::Float64, valueMappingFor(SampleType::Float64, 0.0, 65535.0)));
  for (SampleType type : {SampleType::Int8, SampleType::UInt8, SampleType::Int16, SampleType::UInt16}) {
    EXPECT_FALSE(mapsOverValueRange(type)) << sampleTypeName(type);
    EXPECT_TRUE(isExactMapping(type, valueMappingFor(type, 0, 0))) << sampleTypeName(type);
  }
}

}  // namespace
}  // namespace ropecast
