// Tests of core/transfer_function: parsing and its errors, presets, baking per docs/RENDERING.md, and the
// conservative O(1) opacity test against brute force.
#include "core/transfer_function.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>

#include <gtest/gtest.h>

#include "core/error.h"

namespace ropecast {
namespace {

std::string errorOf(const std::string& json) {
  try {
    TransferFunction::fromJson(json, "test.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(TransferFunction, ParsesPointsAndInterpolatesLinearly) {
  const auto tf =
      TransferFunction::fromJson(R"({"points": [[10, 0, 0, 0, 0], [20, 1, 0.5, 0.25, 0.8]]})", "t");
  ASSERT_EQ(tf.points().size(), 2u);
  EXPECT_EQ(tf.evaluate(0.0), glm::dvec4(0.0));                   // constant below the first point
  EXPECT_EQ(tf.evaluate(30.0), glm::dvec4(1.0, 0.5, 0.25, 0.8));  // and above the last
  const glm::dvec4 mid = tf.evaluate(12.5);
  EXPECT_NEAR(mid.r, 0.25, 1e-12);
  EXPECT_NEAR(mid.g, 0.125, 1e-12);
  EXPECT_NEAR(mid.a, 0.2, 1e-12);
}

TEST(TransferFunction, InterpolatesBetweenPointsMoreThanTheLargestDoubleApart) {
  const TransferFunction tf({TfPoint{-1e308, {0.0, 0.0, 0.0, 0.0}}, TfPoint{1e308, {1.0, 1.0, 1.0, 1.0}}});
  EXPECT_NEAR(tf.evaluate(0.0).a, 0.5, 1e-12);
  EXPECT_NEAR(tf.evaluate(5e307).r, 0.75, 1e-12);
}

TEST(TransferFunction, EqualValuesMakeAStep) {
  const auto tf =
      TransferFunction::fromJson(R"({"points": [[0,0,0,0,0],[5,0,0,0,0],[5,1,1,1,1],[9,1,1,1,1]]})", "t");
  EXPECT_EQ(tf.evaluate(4.999).a, 0.0);
  EXPECT_EQ(tf.evaluate(5.0).a, 1.0);
}

// --tf-range: the first point to LO, the last to HI, the others in proportion; a preset placed by fractions
// of the data range is then placed over [LO, HI].
TEST(TransferFunction, StretchedOverARangeMovesTheFirstPointToLoAndTheLastToHi) {
  const TfDataRange uint8{SampleType::UInt8, 0.0, 255.0};
  const TransferFunction gray = TransferFunction::preset("gray", uint8).stretchedOver(50.0, 150.0);
  const TransferFunction placed =
      TransferFunction::preset("gray", TfDataRange{SampleType::UInt8, 50.0, 150.0});
  ASSERT_EQ(gray.points().size(), placed.points().size());
  for (size_t i = 0; i < gray.points().size(); ++i) {
    EXPECT_NEAR(gray.points()[i].value, placed.points()[i].value, 1e-12) << i;
    EXPECT_EQ(gray.points()[i].rgba, placed.points()[i].rgba) << i;
  }
  const auto file =
      TransferFunction::fromJson(R"({"points": [[100,0,0,0,0],[150,1,0,0,0.5],[300,1,1,1,1]]})", "t");
  const TransferFunction window = file.stretchedOver(-160.0, 240.0);
  EXPECT_EQ(window.points()[0].value, -160.0);
  EXPECT_NEAR(window.points()[1].value, -60.0, 1e-12);
  EXPECT_EQ(window.points()[2].value, 240.0);
  EXPECT_EQ(window.evaluate(-60.0), glm::dvec4(1, 0, 0, 0.5));
  // A step at one value moves to the middle; ranges at the ends of the doubles neither overflow nor reorder.
  const auto step = TransferFunction::fromJson(R"({"points": [[5,0,0,0,0],[5,1,1,1,1]]})", "t");
  EXPECT_EQ(step.stretchedOver(0.0, 10.0).points()[0].value, 5.0);
  EXPECT_EQ(step.stretchedOver(0.0, 10.0).evaluate(5.0).a, 1.0);
  const TransferFunction wide = file.stretchedOver(-1.7e308, 1.7e308);
  EXPECT_EQ(wide.points().front().value, -1.7e308);
  EXPECT_EQ(wide.points().back().value, 1.7e308);
  for (const auto& [lo, hi] : {std::pair{1.0, 1.0}, std::pair{2.0, 1.0}, std::pair{0.0, HUGE_VAL}}) {
    try {
      file.stretchedOver(lo, hi);
      ADD_FAILURE() << lo << "," << hi << " was taken";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("expected LO,HI with LO < HI"), std::string::npos) << e.what();
    }
  }
}

TEST(TransferFunction, ParsingErrorsNameTheFileAndTheProblem) {
  EXPECT_EQ(errorOf(R"({"points": [[0, 0, 0, 0, 0]]})"), "");
  const auto expectError = [](const std::string& json, const std::string& what) {
    const std::string msg = errorOf(json);
    EXPECT_NE(msg.find("test.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << "for " << json << ": " << msg;
  };
  expectError("{\"points\": [[0, 0, 0, 0, 0]", "not valid JSON");
  expectError(R"({"points": [[1e999, 0, 0, 0, 0.1]]})", "not valid JSON");  // out of double range
  expectError("[1, 2]", "expected an object");
  expectError(R"({"points": [[0, 0, 0, 0, 0]], "colorspace": "lab"})", "unknown key \"colorspace\"");
  expectError(R"({"pts": []})", "expected an object");
  expectError(R"({"points": [[0, 1, 0, 0, 1]], "points": [[0, 0, 1, 0, 1]]})",
              "the key \"points\" is given twice");
  expectError(R"({"points": []})", "non-empty array");
  expectError(R"({"points": [[0, 0, 0, 0]]})", "point 0 must be [value, r, g, b, a]");
  expectError(R"({"points": [[0, 0, 0, 0, 0], [1, 0, 0, "red", 0]]})", "point 1 must be");
  expectError(R"({"points": [[0, 0, 0, 0, 0], [1, 0, 0, 0, 1.5]]})", "outside [0, 1]");
  expectError(R"({"points": [[0, 0, 0, 0, 0], [1, -0.1, 0, 0, 0]]})", "outside [0, 1]");
  expectError(R"({"points": [[5, 0, 0, 0, 0], [1, 0, 0, 0, 0]]})", "sorted by value");
  expectError(R"({"points": [[25.5, 0, 0, 0, 0], [1e308, 0, 0, 0, 0], [-1e308, 0, 0, 0, 0]]})",
              "point 2 (-1e+308) comes after 1e+308");
}

TEST(TransferFunction, FileErrorsNameTheFile) {
  const std::string missing = "/nonexistent/dir/tf.json";
  try {
    TransferFunction::fromFile(missing);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  try {
    TransferFunction::fromSpec("no-such-preset-or-file", {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-preset-or-file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ct-bone"), std::string::npos) << e.what();
  }
  const std::string folder = std::filesystem::temp_directory_path().string();
  try {
    TransferFunction::fromSpec(folder, {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + folder + "' is a folder"), std::string::npos) << e.what();
  }
}

TEST(TransferFunction, ExampleFilesLoad) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(ROPECAST_TEST_DATA_DIR) + "/tf")) {
    const auto tf = TransferFunction::fromSpec(entry.path().string(), {});
    EXPECT_GE(tf.points().size(), 2u) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 3);
}

TEST(TransferFunction, CtPresetsStayInHounsfieldForInt16AndScaleOtherwise) {
  const TfDataRange ct{SampleType::Int16, -1024.0, 3071.0};
  const auto boneCt = TransferFunction::preset("ct-bone", ct);
  EXPECT_EQ(boneCt.evaluate(0.0).a, 0.0);    // water is transparent
  EXPECT_GT(boneCt.evaluate(700.0).a, 0.1);  // bone is not
  // uint8 data: the Hounsfield axis [-1024, 3071] is stretched over [0, 255]; 700 HU lands at ~107.
  const TfDataRange u8{SampleType::UInt8, 0.0, 255.0};
  const auto boneU8 = TransferFunction::preset("ct-bone", u8);
  EXPECT_EQ(boneU8.evaluate(1024.0 * 255.0 / 4095.0).a, 0.0);
  EXPECT_NEAR(boneU8.evaluate((700.0 + 1024.0) * 255.0 / 4095.0).a, boneCt.evaluate(700.0).a, 1e-9);
  for (const std::string& name : TransferFunction::presetNames()) {
    if (name == "window") continue;  // a slice's: opaque everywhere (TheWindowPresetIs...)
    const auto tf = TransferFunction::fromSpec(name, u8);
    EXPECT_EQ(tf.evaluate(0.0).a, 0.0) << name << ": the minimum (background) must be transparent";
    EXPECT_GT(tf.evaluate(255.0).a, 0.0) << name;
  }
}

// int32 data is taken as Hounsfield as int16 is, float64 as float32 is (when it reaches below -500); int8 and
// uint32 data get the Hounsfield axis stretched over their range, as uint8 and uint16 do.
TEST(TransferFunction, WiderTypesPlaceCtPresetsAsTheirNarrowerKin) {
  const auto boneAlpha = [](SampleType type, double lo, double hi, double at) {
    return TransferFunction::preset("ct-bone", TfDataRange{type, lo, hi}).evaluate(at).a;
  };
  for (const auto& [lo, hi, at] : {std::tuple{0.0, 4095.0, 700.0}, std::tuple{-1024.0, 5000.0, 700.0},
                                   std::tuple{-128.0, 127.0, 50.0}}) {
    EXPECT_EQ(boneAlpha(SampleType::Int32, lo, hi, at), boneAlpha(SampleType::Int16, lo, hi, at)) << lo;
    EXPECT_EQ(boneAlpha(SampleType::Float64, lo, hi, at), boneAlpha(SampleType::Float32, lo, hi, at)) << lo;
    EXPECT_EQ(boneAlpha(SampleType::UInt32, lo, hi, at), boneAlpha(SampleType::UInt16, lo, hi, at)) << lo;
    EXPECT_EQ(boneAlpha(SampleType::Int8, lo, hi, at), boneAlpha(SampleType::UInt8, lo, hi, at)) << lo;
  }
  // The rules differ where it matters: Hounsfield or stretched.
  EXPECT_NE(boneAlpha(SampleType::Int32, 0.0, 4095.0, 700.0),
            boneAlpha(SampleType::UInt32, 0.0, 4095.0, 700.0));
  EXPECT_NE(boneAlpha(SampleType::Float64, -1024.0, 5000.0, 700.0),
            boneAlpha(SampleType::UInt16, -1024.0, 5000.0, 700.0));
  EXPECT_NE(boneAlpha(SampleType::Int8, -128.0, 127.0, 50.0),
            boneAlpha(SampleType::Int16, -128.0, 127.0, 50.0));
}

// The slice's default: every value opaque, black at the range's low end to white at its high end (a window).
TEST(TransferFunction, TheWindowPresetIsOpaqueBlackToWhiteOverTheRange) {
  const TransferFunction window =
      TransferFunction::preset("window", TfDataRange{SampleType::UInt16, 100.0, 300.0});
  EXPECT_EQ(window.evaluate(100.0), glm::dvec4(0.0, 0.0, 0.0, 1.0));
  EXPECT_EQ(window.evaluate(300.0), glm::dvec4(1.0, 1.0, 1.0, 1.0));
  EXPECT_NEAR(window.evaluate(250.0).r, 0.75, 1e-12);
  EXPECT_EQ(window.evaluate(0.0).a, 1.0);  // below the range: black, still opaque
}

TEST(TransferFunction, PresetsAreKnownByTheirExactNames) {
  for (const std::string& name : TransferFunction::presetNames())
    EXPECT_TRUE(TransferFunction::isPreset(name));
  EXPECT_FALSE(TransferFunction::isPreset("ct-bones"));
  EXPECT_FALSE(TransferFunction::isPreset(""));
  EXPECT_FALSE(TransferFunction::isPreset("tf.json"));
}

TEST(TfTable, BakesEntriesAtNormalizedStoredValuesThroughTheMapping) {
  // int16 data stored as value + 32768 in uint16: entry i sits at data = i/(N-1)*65535 - 32768.
  const auto tf = TransferFunction::fromJson(R"({"points": [[-1000, 0, 0, 0, 0], [1000, 1, 1, 1, 1]]})", "t");
  const ValueMapping mapping = valueMappingFor(SampleType::Int16, 0, 0);
  const TfTable table = TfTable::bake(tf, mapping, 65535, 4096);
  ASSERT_EQ(table.entryCount(), 4096u);
  for (uint32_t i : {0u, 1000u, 2047u, 2048u, 2100u, 4095u}) {
    const double data = double(i) / 4095.0 * 65535.0 - 32768.0;
    EXPECT_NEAR(table.entries()[i].a, tf.evaluate(data).a, 1e-6) << i;
    // lookup at an entry's own position returns that entry
    EXPECT_NEAR(table.lookup(double(i) / 4095.0).a, table.entries()[i].a, 1e-6) << i;
  }
  // Between entries the lookup is linear: halfway between 2047 and 2048.
  const double half = (2047.5) / 4095.0;
  EXPECT_NEAR(table.lookup(half).a, 0.5 * (table.entries()[2047].a + table.entries()[2048].a), 1e-7);
  // Clamped outside [0, 1].
  EXPECT_EQ(table.lookup(-1.0), glm::dvec4(table.entries()[0]));
  EXPECT_EQ(table.lookup(2.0), glm::dvec4(table.entries()[4095]));
}

// Brute force: the largest opacity lookup() gives over the stored range [lo, hi], sampling every table cell
// the range touches at its ends and at the range's own ends.
bool bruteForceHasOpacity(const TfTable& t, uint32_t lo, uint32_t hi) {
  const double n1 = t.entryCount() - 1;
  const double vlo = double(lo) / t.storedMax(), vhi = double(hi) / t.storedMax();
  if (t.lookup(vlo).a > 0.0 || t.lookup(vhi).a > 0.0) return true;
  for (double x = std::ceil(vlo * n1); x <= vhi * n1; x += 1.0)
    if (t.lookup(x / n1).a > 0.0) return true;
  // Also a dense sweep of the continuous range (interpolated values between integers).
  for (int k = 0; k <= 64; ++k)
    if (t.lookup(vlo + (vhi - vlo) * k / 64.0).a > 0.0) return true;
  return false;
}

TEST(TfTable, HasOpacityIsConservativeAndUseful) {
  std::mt19937 rng(42);
  for (uint32_t storedMax : {255u, 65535u}) {
    for (int trial = 0; trial < 20; ++trial) {
      // A random TF with transparent gaps: alternate zero and non-zero alpha runs, sometimes with steps.
      std::vector<TfPoint> pts;
      double value = 0.0;
      std::uniform_real_distribution<double> gap(0.0, storedMax / 6.0);
      bool opaque = false;
      while (value < storedMax) {
        const double a = opaque ? 0.01 + 0.5 * std::uniform_real_distribution<double>()(rng) : 0.0;
        pts.push_back({value, {0.5, 0.5, 0.5, a}});
        value += (rng() % 4 == 0) ? 0.0 : gap(rng);
        pts.push_back({value, {0.5, 0.5, 0.5, a}});
        value += gap(rng);
        opaque = !opaque;
      }
      const TfTable table = TfTable::bake(TransferFunction(pts), {1.0, 0.0}, storedMax, 4096);
      int falseAnswers = 0;
      for (int q = 0; q < 2000; ++q) {
        uint32_t lo = rng() % (storedMax + 1), hi = rng() % (storedMax + 1);
        if (q % 2 == 0)
          hi = std::min(storedMax, lo + uint32_t(rng() % (storedMax / 50 + 1)));  // narrow ranges
        if (lo > hi) std::swap(lo, hi);
        const bool brute = bruteForceHasOpacity(table, lo, hi);
        const bool fast = table.hasOpacity(lo, hi);
        if (brute) {
          EXPECT_TRUE(fast) << "range [" << lo << ", " << hi << "] has opacity, storedMax " << storedMax;
        }
        if (!fast) ++falseAnswers;
      }
      EXPECT_GT(falseAnswers, 0) << "the test never rules a range out: it would be trivially conservative";
    }
  }
}

TEST(TfTable, HasOpacityAtTheEdgeOfAnOpaqueRun) {
  // Opaque only at stored value 200 (uint8): ranges just touching it are visible, ranges well away are not.
  const auto tf = TransferFunction::fromJson(
      R"({"points": [[0,0,0,0,0],[199,0,0,0,0],[200,1,1,1,1],[201,0,0,0,0]]})", "t");
  const TfTable table = TfTable::bake(tf, {1.0, 0.0}, 255, 4096);
  EXPECT_TRUE(table.hasOpacity(200, 200));
  EXPECT_TRUE(table.hasOpacity(150, 200));
  EXPECT_TRUE(table.hasOpacity(200, 255));
  EXPECT_TRUE(table.hasOpacity(0, 255));
  EXPECT_FALSE(table.hasOpacity(0, 198));
  EXPECT_FALSE(table.hasOpacity(202, 255));
}

}  // namespace
}  // namespace ropecast
