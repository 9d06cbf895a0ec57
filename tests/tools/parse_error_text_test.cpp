// Command-line parse errors in ropecast's words: the option, what it expected and what it got, the options a
// mistyped one was probably meant to be, and the command whose --help lists them.
#include "tools/parse_error_text.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "tools/cli_values.h"

namespace ropecast::tools {
namespace {

// A program with a subcommand "render" shaped like ropecast's: a positional input and a few options.
struct Program {
  CLI::App app{"ropecast"};
  std::string input, output;
  std::vector<double> orbit;
  std::vector<uint32_t> size;
  double iso = 0.5;
  uint32_t frames = 1, brick = 32, level = 0;
  double voxelsPerPixel = 1.0;

  Program() {
    app.require_subcommand(1);
    CLI::App* render = app.add_subcommand("render");
    render->add_option("input", input, "store file (.rcast) or procedural:NAME:SIZE")->required();
    render->add_option("-o,--output", output, "output PNG");
    addTripleOption(*render, "--orbit", orbit, "AZ,EL,DIST");
    addImageSizeOption(*render, "--size", size, "WxH");
    render->add_option("--iso", iso);
    render->add_option("--frames", frames)->transform(integerRange(1, 1000000));
    render->add_option("--brick", brick)->check(oneOf(std::vector<uint32_t>{8, 16, 32, 64}));
    render->add_option("--voxels-per-pixel", voxelsPerPixel);
    render->add_option("--voxel-size", voxelsPerPixel);
    render->add_option("--level", level);
  }

  // The text for `args` (after the program name), or "" when they parse.
  std::string errorFor(std::vector<std::string> args) {
    std::reverse(args.begin(), args.end());
    try {
      app.parse(args);
    } catch (const CLI::ParseError& e) {
      return parseErrorText(app, e) + " | " + parsedCommandPath(app);
    }
    return "";
  }
};

TEST(ParseErrorText, UnknownOptionsNameTheOptionsMeant) {
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--voxel-per-pixel", "2"}),
            "unknown option --voxel-per-pixel (did you mean --voxels-per-pixel?) | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--frmaes=3"}),
            "unknown option --frmaes (did you mean --frames?) | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--outpt", "a.png"}),
            "unknown option --outpt (did you mean --output?) | ropecast render");
  // Nothing close: no guess. The word after an unknown option is taken as its value.
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--colormap", "jet", "--cmap=jet", "more"}),
            "unknown option --colormap; unknown option --cmap; unexpected argument 'more' | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "y.rcast"}),
            "unexpected argument 'y.rcast' | ropecast render");
}

TEST(ParseErrorText, CountsSayWhatTheOptionTakes) {
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--orbit", "30,20"}),
            "--orbit: expected 3 values separated by ',', got 2 | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--size", "512"}),
            "--size: expected 2 values separated by 'x', got 1 | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--iso"}),
            "--iso: expected a value (FLOAT) after it | ropecast render");
}

TEST(ParseErrorText, ValuesOutOfTheirRangeOrSet) {
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--frames", "0"}),
            "--frames: expected an integer in [1, 1000000], got '0' | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--frames", "2.5"}),
            "--frames: expected an integer in [1, 1000000], got '2.5' | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--level", "abc"}),
            "--level: expected an integer >= 0, got 'abc' | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--iso", "1..2"}),
            "--iso: expected a number, got '1..2' | ropecast render");
  EXPECT_EQ(Program().errorFor({"render", "x.rcast", "--brick", "7"}),
            "--brick: expected 8, 16, 32 or 64, got '7' | ropecast render");
  Program accepted;
  EXPECT_EQ(accepted.errorFor({"render", "x.rcast", "--frames", "2e3", "--brick", "16"}), "");
  EXPECT_EQ(accepted.frames, 2000u);
  EXPECT_EQ(accepted.brick, 16u);
}

TEST(ParseErrorText, MissingInputsAndCommands) {
  EXPECT_EQ(Program().errorFor({"render"}),
            "missing input: store file (.rcast) or procedural:NAME:SIZE | ropecast render");
  EXPECT_EQ(Program().errorFor({}), "a command is required: render | ropecast");
}

TEST(ParseErrorText, LikelyMeantTakesNearAndBegunNames) {
  const std::vector<std::string> options{"--gpu-budget", "--cpu-cache", "--upload-budget",
                                         "--upload-pbo", "--iso",       "--io-threads"};
  EXPECT_EQ(likelyMeant("--gpu-budgte", options), std::vector<std::string>{"--gpu-budget"});
  EXPECT_EQ(likelyMeant("--upload", options), (std::vector<std::string>{"--upload-pbo", "--upload-budget"}));
  EXPECT_EQ(likelyMeant("--isp", options), std::vector<std::string>{"--iso"});
  EXPECT_EQ(likelyMeant("--cache", options), std::vector<std::string>{});
  EXPECT_EQ(likelyMeant("-x", options), std::vector<std::string>{});
  EXPECT_EQ(likelyMeant("---", options), std::vector<std::string>{});
  EXPECT_EQ(likelyMeant("--=3", options), std::vector<std::string>{});
}

}  // namespace
}  // namespace ropecast::tools
