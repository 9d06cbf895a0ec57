// The command line's compound and enumerated values as CLI11 parses them: accepted forms, and errors that
// name the option.
#include "tools/cli_values.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "core/render_params.h"
#include "core/sample_type.h"

namespace ropecast::tools {
namespace {

// Parses `args` (without the program name); CLI11's error message, or "" when they were accepted.
std::string parse(CLI::App& app, std::vector<std::string> args) {
  std::reverse(args.begin(), args.end());  // CLI::App::parse(vector) takes them last to first
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

// `option value` with a fresh option of the given kind: the error, or "" with the parsed value in `out`.
template <typename T, typename Add>
std::string parseOne(Add add, const std::string& option, const std::string& value, T& out) {
  CLI::App app;
  add(app, option, out, "help");
  return parse(app, {option, value});
}

TEST(CliValues, ParsesTriples) {
  std::vector<double> v;
  EXPECT_EQ(parseOne(addTripleOption, "--eye", "1.5,2,-3", v), "");
  EXPECT_EQ(toVec3(v), glm::dvec3(1.5, 2, -3));
  v.clear();
  EXPECT_EQ(parseOne(addTripleOption, "--up", " 0, 0 ,1e2", v), "");
  EXPECT_EQ(toVec3(v), glm::dvec3(0, 0, 100));
  for (const char* bad : {"", "1,2", "1,2,3,4", "a,b,c", "1,,3", "1,2,nan", "1,inf,2"}) {
    v.clear();
    const std::string message = parseOne(addTripleOption, "--eye", bad, v);
    EXPECT_NE(message.find("--eye"), std::string::npos) << "'" << bad << "' gave: " << message;
  }
  EXPECT_EQ(formatTriple({1, 0.5, -2}), "1,0.5,-2");
}

TEST(CliValues, ParsesTriplesInARange) {
  const auto unit = [](CLI::App& app, const std::string& name, std::vector<double>& xyz,
                       const std::string& help) { return addTripleOptionIn(app, name, xyz, help, 0.0, 1.0); };
  std::vector<double> v;
  EXPECT_EQ(parseOne(unit, "--background", "0,0.5,1", v), "");
  EXPECT_EQ(toVec3(v), glm::dvec3(0, 0.5, 1));
  for (const char* bad : {"-1,5,0.5", "0,0,1.01", "0,nan,0"}) {
    v.clear();
    const std::string message = parseOne(unit, "--background", bad, v);
    EXPECT_NE(message.find("--background: expected a finite number in [0, 1]"), std::string::npos)
        << "'" << bad << "' gave: " << message;
  }
}

TEST(CliValues, ParsesDims) {
  std::vector<uint32_t> v;
  EXPECT_EQ(parseOne(addDimsOption, "--dims", "301,370,316", v), "");
  EXPECT_EQ(v, (std::vector<uint32_t>{301, 370, 316}));
  for (const char* bad : {"0,1,1", "-1,2,3", "1.5,2,3", "1,2", "x", "1,2,4294967296"}) {
    v.clear();
    const std::string message = parseOne(addDimsOption, "--dims", bad, v);
    EXPECT_NE(message.find("--dims"), std::string::npos) << "'" << bad << "' gave: " << message;
  }
}

TEST(CliValues, ParsesImageSizes) {
  std::vector<uint32_t> v;
  EXPECT_EQ(parseOne(addImageSizeOption, "--size", "512x256", v), "");
  EXPECT_EQ(v, (std::vector<uint32_t>{512, 256}));
  v.clear();
  EXPECT_EQ(parseOne(addImageSizeOption, "--size", "1x1", v), "");
  EXPECT_EQ(v, (std::vector<uint32_t>{1, 1}));
  for (const char* bad : {"512", "0x10", "512x", "x512", "100000x10", "-5x5", "5*5", "512x512x2"}) {
    v.clear();
    const std::string message = parseOne(addImageSizeOption, "--size", bad, v);
    EXPECT_NE(message.find("--size"), std::string::npos) << "'" << bad << "' gave: " << message;
  }
  // A default is replaced, not appended to.
  CLI::App app;
  std::vector<uint32_t> size{512, 512};
  addImageSizeOption(app, "--size", size, "help");
  EXPECT_EQ(parse(app, {"--size", "64x32"}), "");
  EXPECT_EQ(size, (std::vector<uint32_t>{64, 32}));
}

TEST(CliValues, ParsesByteSizesInBinaryUnits) {
  const std::pair<const char*, uint64_t> good[] = {{"1073741824", uint64_t(1) << 30},
                                                   {"512M", uint64_t(512) << 20},
                                                   {"2G", uint64_t(2) << 30},
                                                   {"64K", uint64_t(64) << 10},
                                                   {"1.5G", uint64_t(3) << 29},
                                                   {"2GiB", uint64_t(2) << 30},
                                                   {"2gb", uint64_t(2) << 30},
                                                   {"100B", 100},
                                                   {"0", 0},
                                                   {"16T", uint64_t(16) << 40}};
  for (const auto& [text, bytes] : good) {
    uint64_t v = 0;
    EXPECT_EQ(parseOne(addByteSizeOption, "--cpu-cache", text, v), "") << text;
    EXPECT_EQ(v, bytes) << text;
  }
  for (const char* bad : {"", "M", "-1G", "12Q", "1..5G", "lots", "2P", "1e30", "nan"}) {
    uint64_t v = 0;
    const std::string message = parseOne(addByteSizeOption, "--gpu-budget", bad, v);
    EXPECT_NE(message.find("--gpu-budget"), std::string::npos) << "'" << bad << "' gave: " << message;
  }
}

TEST(CliValues, RefusesAZeroSizeWhereZeroWouldMeanTheDefault) {
  const auto addBudget = [](CLI::App& app, const std::string& name, uint64_t& bytes,
                            const std::string& help) {
    return addByteSizeOption(app, name, bytes, help)->check(nonZeroSize("leave it out for the default"));
  };
  uint64_t v = 0;
  EXPECT_EQ(parseOne(addBudget, "--gpu-budget", "1K", v), "");
  EXPECT_EQ(v, 1024u);
  for (const char* zero : {"0", "0M", "0.0G"}) {
    const std::string message = parseOne(addBudget, "--gpu-budget", zero, v);
    EXPECT_NE(message.find("--gpu-budget"), std::string::npos) << zero << " gave: " << message;
    EXPECT_NE(message.find("leave it out for the default"), std::string::npos) << message;
  }
}

TEST(CliValues, MapsNamesStraightToEnums) {
  const std::vector<std::pair<std::string, RenderBackend>> names{{"auto", RenderBackend::Auto},
                                                                 {"compute", RenderBackend::Compute}};
  {
    CLI::App app;
    RenderBackend backend = RenderBackend::Auto;
    addEnumOption(app, "--backend", backend, names, "help");
    EXPECT_EQ(parse(app, {"--backend", "compute"}), "");
    EXPECT_EQ(backend, RenderBackend::Compute);
    EXPECT_NE(app.help().find("{auto,compute}"), std::string::npos) << app.help();
    EXPECT_NE(app.help().find("auto"), std::string::npos) << app.help();
  }
  for (const char* bad : {"vulkan", "1", "Compute", ""}) {
    CLI::App app;
    RenderBackend backend = RenderBackend::Auto;
    addEnumOption(app, "--backend", backend, names, "help");
    const std::string message = parse(app, {"--backend", bad});
    EXPECT_NE(message.find("--backend"), std::string::npos) << "'" << bad << "' gave: " << message;
    EXPECT_EQ(backend, RenderBackend::Auto) << bad;
  }
}

TEST(CliValues, SampleTypesIgnoreCaseAndTakeAliases) {
  std::vector<std::pair<std::string, SampleType>> names;
  for (const auto& [name, type] : kSampleTypeNames) names.emplace_back(name, type);
  for (const auto& [text, type] :
       {std::pair{"uint16", SampleType::UInt16}, std::pair{"U8", SampleType::UInt8},
        std::pair{"Unsigned Short", SampleType::UInt16}, std::pair{"float", SampleType::Float32},
        std::pair{"I8", SampleType::Int8}, std::pair{"unsigned int", SampleType::UInt32},
        std::pair{"INT", SampleType::Int32}, std::pair{"Double", SampleType::Float64}}) {
    CLI::App app;
    std::optional<SampleType> parsed;
    addEnumOption(app, "--type", parsed, names, "help", /*ignoreCase=*/true);
    EXPECT_EQ(parse(app, {"--type", text}), "") << text;
    EXPECT_EQ(parsed, type) << text;
  }
  for (const char* unknown : {"int64", "char"}) {  // no 64-bit integers; "char" does not say its sign
    CLI::App app;
    std::optional<SampleType> parsed;
    addEnumOption(app, "--type", parsed, names, "help", /*ignoreCase=*/true);
    EXPECT_NE(parse(app, {"--type", unknown}).find("--type"), std::string::npos) << unknown;
    EXPECT_FALSE(parsed) << unknown;
  }
}

TEST(VoxelRange, HalfOpenRangesWithEitherBoundLeftOut) {
  const auto range = [](std::string_view text) { return parseVoxelRange(text); };
  ASSERT_TRUE(range("3:10"));
  EXPECT_EQ(range("3:10")->begin, 3u);
  EXPECT_EQ(range("3:10")->end, 10u);
  EXPECT_EQ(range(" 3 : 10 ")->end, 10u);
  EXPECT_FALSE(range("3:")->end);
  EXPECT_EQ(range("3:")->begin, 3u);
  EXPECT_FALSE(range(":10")->begin);
  EXPECT_TRUE(range(":"));
  for (const char* bad :
       {"", "3", "10:3", "4:4", "-1:3", "+1:3", "1.5:3", "a:b", "1:2:3", "0:99999999999999999999"})
    EXPECT_FALSE(range(bad)) << bad;
  EXPECT_EQ(splitVoxelRanges("1:2,:,3:"), (std::vector<std::string>{"1:2", ":", "3:"}));
  for (const char* bad : {"1:2,:", "1:2,:,:,:", "1:2,,:", "1:2;:;:", ""})
    EXPECT_FALSE(splitVoxelRanges(bad)) << bad;
}

}  // namespace
}  // namespace ropecast::tools
