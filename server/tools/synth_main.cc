// omnisweep-synth: renders frames of the synthetic rig with exact ground truth and writes them
// as a dataset in the reference layout, plus a colourised inverse-distance preview.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "client_sdk/tools/cli_checks.h"
#include "client_sdk/tools/tool_main.h"
#include "omnisweep/image/image_io.h"
#include "omnisweep/rig/basalt_calibration.h"
#include "server/synthetic/synthetic_dataset.h"

namespace {

using omnisweep::synthetic::SyntheticRig;
using omnisweep::synthetic::SyntheticRigOptions;
using omnisweep::synthetic::WriteDatasetOptions;

int run(int argc, char** argv) {
  CLI::App app{
      "Render frames of the synthetic four-fisheye rig, with exact ground truth, as a dataset "
      "in the reference layout (calibration.json, cam<i>/, gt/)."};
  std::string output, calibration;
  SyntheticRigOptions rig_options;
  WriteDatasetOptions write;
  std::vector<int> panorama = {2048, 1024};
  app.add_option("--output,-o", output, "Dataset folder to write (created if missing)")->required();
  app.add_option("--frames,-n", write.num_frames, "Number of frames")->check(CLI::Range(1, 100000));
  app.add_option("--first-frame", write.first_frame, "Index of the first frame on the rig's path")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", rig_options.seed, "Scene seed (same seed, same scene)")
      ->check(omnisweep::tools::not_negative());
  app.add_option("--image-size", rig_options.image_size,
                 "Fisheye width and height of the default rig")
      ->check(CLI::Range(16, 8192));
  app.add_option("--calibration", calibration, "Render through this basalt calibration instead")
      ->check(CLI::ExistingFile);
  app.add_option("--panorama", panorama, "Ground-truth panorama width and height")
      ->expected(2)
      ->check(CLI::Range(8, 16384));
  app.add_option("--references", rig_options.references,
                 "Reference cameras; the viewpoint is their mean")
      ->expected(1, 16);
  app.add_option("--frames-per-loop", rig_options.frames_per_loop,
                 "Frames in one lap of the rig's path")
      ->check(CLI::PositiveNumber);
  app.add_flag("--static-rig", rig_options.static_rig,
               "Keep the rig at the path's first pose in every frame (a static scene for the "
               "temporal filter; --noise still changes every frame)");
  app.add_option("--lens-fov", rig_options.lens_half_fov_deg,
                 "Half field of view of the lenses, degrees")
      ->check(CLI::Range(1.0, 180.0));
  bool realistic = false;
  double gain_spread = -1, color_cast = -1, noise = -1;
  std::vector<double> vignetting;
  app.add_flag("--photometric", realistic,
               "Give the cameras the realistic gains, colour casts and vignetting the robustness "
               "targets use (gain 0.75-1.25, cast +-6 %, 45-65 % brightness at 110 degrees); "
               "the options below override single parts");
  app.add_option("--gain-spread", gain_spread, "Per-camera gain uniform in [1 - S, 1 + S]")
      ->check(CLI::Range(0.0, 0.9));
  app.add_option("--color-cast", color_cast,
                 "Per-camera, per-channel colour factor uniform in [1 - C, 1 + C]")
      ->check(CLI::Range(0.0, 0.5));
  app.add_option("--vignetting", vignetting,
                 "Per-camera brightness left at 110 degrees off axis, uniform in [LO, HI]")
      ->expected(2)
      ->check(CLI::Range(0.05, 1.0));
  app.add_option("--noise", noise, "Gaussian sensor noise, 8-bit levels, new every frame")
      ->check(CLI::Range(0.0, 64.0));
  CLI11_PARSE(app, argc, argv);
  auto& photometric = rig_options.photometric;
  if (realistic) photometric = omnisweep::synthetic::PhotometricOptions::realistic();
  if (gain_spread >= 0) photometric.gain_spread = gain_spread;
  if (color_cast >= 0) photometric.color_cast = color_cast;
  if (noise >= 0) photometric.noise_sigma = noise;
  if (!vignetting.empty()) {
    if (vignetting[0] > vignetting[1]) {
      std::fprintf(stderr, "omnisweep-synth: --vignetting %g %g: LO must not exceed HI\n",
                   vignetting[0], vignetting[1]);
      return 2;
    }
    photometric.vignetting_min = vignetting[0];
    photometric.vignetting_max = vignetting[1];
  }
  if (panorama[0] != 2 * panorama[1]) {
    std::fprintf(stderr, "omnisweep-synth: --panorama %d %d: width must be twice the height\n",
                 panorama[0], panorama[1]);
    return 2;
  }
  write.panorama_width = panorama[0];
  write.panorama_height = panorama[1];

  omnisweep::Rig user_rig;
  if (!calibration.empty()) user_rig = omnisweep::read_basalt_calibration(calibration);
  const SyntheticRig rig(rig_options, calibration.empty() ? nullptr : &user_rig);

  const auto stats = write_synthetic_dataset(rig, output, write, [&](int done, int total) {
    if (total > 1) std::fprintf(stderr, "\rframe %d/%d", done, total);
    if (total > 1 && done == total) std::fprintf(stderr, "\n");
  });

  // A preview of the last frame's ground-truth distance for people to look at.
  const std::string last = std::to_string(write.first_frame + write.num_frames - 1);
  const std::filesystem::path preview = std::filesystem::path(output) / "preview";
  std::filesystem::create_directories(preview);
  const auto inv =
      omnisweep::read_exr(std::filesystem::path(output) / "gt" / ("inv_distance_" + last + ".exr"));
  omnisweep::write_png(preview / ("inv_distance_" + last + ".png"),
                       omnisweep::colorize_inverse_distance(inv, 1.0f / 0.55f));

  const auto& cam = rig.rig().cameras[0];
  std::printf(
      "rendered %d frame(s) of %d x %dx%d fisheye images and a %dx%d panorama: %.2f s per frame "
      "(ray casting %.2f s, writing files %.2f s)\n",
      write.num_frames, rig.rig().num_cameras(), cam.width, cam.height, write.panorama_width,
      write.panorama_height, (stats.render_seconds + stats.write_seconds) / write.num_frames,
      stats.render_seconds / write.num_frames, stats.write_seconds / write.num_frames);
  std::printf("dataset:                %s\n", std::filesystem::absolute(output).c_str());
  std::printf(
      "ground-truth panorama:  %s\n",
      std::filesystem::absolute(std::filesystem::path(output) / "gt" / ("rgb_" + last + ".png"))
          .c_str());
  std::printf("ground-truth distance:  %s\n",
              std::filesystem::absolute(preview / ("inv_distance_" + last + ".png")).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-synth", argc, argv, run);
}
