// The shared depth flags as the programs parse them: --method sets the matching variants at once,
// a variant's own flag overrides it wherever it stands, and a bad name is named in the error.
#include "server/tools/depth_flags.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace omnisweep::tools {
namespace {

depth::DepthOptions parsed(std::vector<std::string> args) {
  depth::DepthOptions options;
  std::string device;
  CLI::App app;
  add_depth_flags(app, options, device);
  args.insert(args.begin(), "omnisweep-test");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  app.parse(int(argv.size()), argv.data());
  return options;
}

TEST(DepthFlagsTest, MethodRecommendedSetsTheVariantsAndPaperIsTheDefaults) {
  const depth::DepthOptions defaults;
  const depth::DepthOptions recommended = parsed({"--method", "recommended"});
  EXPECT_EQ(recommended.cost, depth::MatchingCost::kAbsoluteDifference);
  EXPECT_TRUE(recommended.correct_photometry);
  EXPECT_EQ(recommended.match_cameras, 2);
  EXPECT_EQ(recommended.confident_sigma_s, 5.0);
  EXPECT_EQ(recommended.sigma_s, defaults.sigma_s);  // only the variants change
  EXPECT_EQ(recommended.coarse_agreement, defaults.coarse_agreement);

  const depth::DepthOptions paper = parsed({"--method", "paper"});
  EXPECT_EQ(paper.cost, defaults.cost);
  EXPECT_EQ(paper.correct_photometry, defaults.correct_photometry);
  EXPECT_EQ(paper.match_cameras, defaults.match_cameras);
  EXPECT_EQ(paper.confident_sigma_s, defaults.confident_sigma_s);
  EXPECT_EQ(parsed({}).confident_sigma_s, 0.0);
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
    EXPECT_NE(what.find("unknown method 'best' (one of paper, recommended)"), std::string::npos)
        << what;
  }
  depth::DepthOptions options;
  EXPECT_FALSE(depth::apply_method("Paper", options));
  EXPECT_EQ(options.match_cameras, 1);
}

TEST(DepthFlagsTest, AMethodsFlagsComeFromItsTable) {
  EXPECT_EQ(depth::method_flags(depth::kMethods[0]), "");
  EXPECT_EQ(depth::method_flags(depth::kMethods[1]),
            "--correct-photometry --match-cameras 2 --confident-sigma-s 5");
  const depth::Method ratio{"r", depth::MatchingCost::kRatio, false, 2, 0.0};
  EXPECT_EQ(depth::method_flags(ratio), "--cost ratio --match-cameras 2");
}

}  // namespace
}  // namespace omnisweep::tools
