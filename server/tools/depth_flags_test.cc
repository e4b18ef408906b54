// The shared depth flags as the programs parse them: --method sets the variants at once ("accurate"
// unless named), a variant's own flag overrides it wherever it stands, and a bad name is named in
// the error.
#include "server/tools/depth_flags.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "server/tools/stitch_flags.h"

namespace omnisweep::tools {
namespace {

// The parsed flags: the depth options and the stitcher's variants that a method sets.
struct Parsed {
  depth::DepthOptions options;
  double plane_fill = 0;
  bool region_planes = false;
};

Parsed parse(std::vector<std::string> args) {
  Parsed p;
  std::string device;
  CLI::App app;
  add_depth_flags(app, p.options, device, {&p.plane_fill, &p.region_planes});
  add_plane_fill_flag(app, p.plane_fill);
  add_region_planes_flag(app, p.region_planes);
  args.insert(args.begin(), "omnisweep-test");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  app.parse(int(argv.size()), argv.data());
  return p;
}

depth::DepthOptions parsed(std::vector<std::string> args) { return parse(std::move(args)).options; }

TEST(DepthFlagsTest, AccurateIsTheDefaultAndEachMethodSetsItsVariants) {
  const depth::DepthOptions paper_defaults;  // DepthOptions' own: ALGORITHM.md
  const Parsed none = parse({});
  EXPECT_EQ(none.options.cost, depth::MatchingCost::kAbsoluteDifference);
  EXPECT_TRUE(none.options.correct_photometry);
  EXPECT_EQ(none.options.match_cameras, 2);
  EXPECT_EQ(none.options.confident_sigma_s, 5.0);
  EXPECT_EQ(none.options.sigma_s, 20.0);
  EXPECT_EQ(none.plane_fill, 0.05);
  EXPECT_TRUE(none.region_planes);
  EXPECT_EQ(none.options.coarse_agreement, paper_defaults.coarse_agreement);  // not a variant

  const Parsed paper = parse({"--method", "paper"});
  EXPECT_EQ(paper.options.cost, paper_defaults.cost);
  EXPECT_EQ(paper.options.correct_photometry, paper_defaults.correct_photometry);
  EXPECT_EQ(paper.options.match_cameras, paper_defaults.match_cameras);
  EXPECT_EQ(paper.options.confident_sigma_s, paper_defaults.confident_sigma_s);
  EXPECT_EQ(paper.options.sigma_s, paper_defaults.sigma_s);
  EXPECT_EQ(paper.plane_fill, 0.0);
  EXPECT_FALSE(paper.region_planes);

  const Parsed recommended = parse({"--method", "recommended"});
  EXPECT_TRUE(recommended.options.correct_photometry);
  EXPECT_EQ(recommended.options.match_cameras, 2);
  EXPECT_EQ(recommended.options.confident_sigma_s, 5.0);
  EXPECT_EQ(recommended.options.sigma_s, paper_defaults.sigma_s);
  EXPECT_EQ(recommended.plane_fill, 0.0);
  EXPECT_FALSE(recommended.region_planes);
}

TEST(DepthFlagsTest, TheStitchersVariantsOverrideTheMethodWhereverTheyStand) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--method", "paper", "--plane-fill", "0.1", "--region-planes", "--sigma-s", "30"},
           {"--plane-fill", "0.1", "--region-planes", "--sigma-s", "30", "--method", "paper"}}) {
    const Parsed p = parse(args);
    EXPECT_EQ(p.plane_fill, 0.1);
    EXPECT_TRUE(p.region_planes);
    EXPECT_EQ(p.options.sigma_s, 30.0);
    EXPECT_FALSE(p.options.correct_photometry);  // still the method's
  }
  const Parsed off = parse({"--no-region-planes", "--no-correct-photometry"});
  EXPECT_FALSE(off.region_planes);
  EXPECT_FALSE(off.options.correct_photometry);
  EXPECT_EQ(off.plane_fill, 0.05);  // the rest of the default method
}

TEST(DepthFlagsTest, AVariantsOwnFlagOverridesTheMethodWhereverItStands) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--method", "recommended", "--match-cameras", "1", "--confident-sigma-s", "8"},
           {"--match-cameras", "1", "--confident-sigma-s", "8", "--method", "recommended"}}) {
    const depth::DepthOptions options = parsed(args);
    EXPECT_EQ(options.match_cameras, 1);
    EXPECT_EQ(options.confident_sigma_s, 8.0);
    EXPECT_TRUE(options.correct_photometry);  // still the method's
  }
  const depth::DepthOptions ratio = parsed({"--cost", "ratio", "--method", "paper"});
  EXPECT_EQ(ratio.cost, depth::MatchingCost::kRatio);
}

TEST(DepthFlagsTest, AnUnknownMethodIsNamedWithTheChoices) {
  try {
    parsed({"--method", "best"});
    FAIL() << "--method best was accepted";
  } catch (const CLI::ValidationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown method 'best' (one of paper, recommended, accurate)"),
              std::string::npos)
        << what;
  }
  depth::DepthOptions options;
  EXPECT_FALSE(depth::apply_method("Paper", options));
  EXPECT_EQ(options.match_cameras, 1);
}

TEST(DepthFlagsTest, MatchBlurIsOffInEveryMethodAndTakesItsFlag) {
  for (const depth::Method& method : depth::kMethods)
    EXPECT_EQ(parsed({"--method", std::string(method.name)}).match_blur, 0.0) << method.name;
  EXPECT_EQ(parsed({"--match-blur", "1.5"}).match_blur, 1.5);
  EXPECT_EQ(parsed({"--match-blur", "1", "--method", "paper"}).match_blur, 1.0);
  EXPECT_THROW(parsed({"--match-blur", "3"}), CLI::ValidationError);  // taps past 8 pixels
  EXPECT_THROW(parsed({"--match-blur", "-1"}), CLI::ValidationError);
}

TEST(DepthFlagsTest, AMethodsFlagsComeFromItsTable) {
  EXPECT_EQ(depth::method_flags(depth::kMethods[0]), "");
  EXPECT_EQ(depth::method_flags(depth::kMethods[1]),
            "--correct-photometry --match-cameras 2 --confident-sigma-s 5");
  EXPECT_EQ(depth::method_flags(depth::kMethods[2]),
            "--correct-photometry --match-cameras 2 --confident-sigma-s 5 --sigma-s 20 "
            "--plane-fill 0.05 --region-planes");
  const depth::Method ratio{"r", depth::MatchingCost::kRatio, false, 2, 0.0, 25.0, 0.0, false};
  EXPECT_EQ(depth::method_flags(ratio), "--cost ratio --match-cameras 2");
}

}  // namespace
}  // namespace omnisweep::tools
