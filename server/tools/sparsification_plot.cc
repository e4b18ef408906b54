#include "server/tools/sparsification_plot.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace omnisweep::tools {
namespace {

// Drawn with OpenCV's primitives: no plotting library is among the project's dependencies, and
// two polylines with axes need none.
void draw_curve(cv::Mat& canvas, const std::vector<double>& x, const std::vector<double>& y,
                const cv::Rect& area, double y_max, const cv::Scalar& color) {
  std::vector<cv::Point> points;
  for (std::size_t i = 0; i < x.size(); ++i) {
    points.emplace_back(area.x + int(x[i] * area.width),
                        area.y + area.height - int(std::min(y[i] / y_max, 1.0) * area.height));
  }
  cv::polylines(canvas, points, false, color, 2, cv::LINE_AA);
}

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace

Rgb8Image plot_sparsification(const stitch::Sparsification& curve, const std::string& title,
                              int width, int height) {
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect area(70, 40, width - 100, height - 100);
  double y_max = 0;
  for (const double v : curve.mae) y_max = std::max(y_max, v);
  y_max = y_max > 0 ? y_max * 1.05 : 1.0;
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200);
  for (int i = 0; i <= 5; ++i) {  // grid and tick labels
    const int y = area.y + area.height - i * area.height / 5;
    const int x = area.x + i * area.width / 5;
    cv::line(canvas, {area.x, y}, {area.x + area.width, y}, grey, 1);
    cv::line(canvas, {x, area.y}, {x, area.y + area.height}, grey, 1);
    cv::putText(canvas, format("%.3f", y_max * i / 5), {5, y + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                black, 1, cv::LINE_AA);
    cv::putText(canvas, format("%.0f %%", 20.0 * i), {x - 12, area.y + area.height + 18},
                cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  }
  cv::rectangle(canvas, area, black, 1);
  // Colours are RGB: the image goes out as RGB (Rgb8Image), not through OpenCV's BGR.
  draw_curve(canvas, curve.removed, curve.oracle, area, y_max, cv::Scalar(150, 150, 150));
  draw_curve(canvas, curve.removed, curve.mae, area, y_max, cv::Scalar(0, 90, 200));
  cv::putText(canvas, title, {area.x, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.55, black, 1, cv::LINE_AA);
  cv::putText(canvas, "share of pixels removed, least confident first",
              {area.x + area.width / 2 - 170, height - 15}, cv::FONT_HERSHEY_SIMPLEX, 0.45, black,
              1, cv::LINE_AA);
  const int legend_x = area.x + area.width - 230;
  cv::line(canvas, {legend_x, area.y + 15}, {legend_x + 25, area.y + 15}, cv::Scalar(0, 90, 200),
           2);
  cv::putText(canvas, format("by confidence, AUSE %.4f", curve.ause), {legend_x + 30, area.y + 19},
              cv::FONT_HERSHEY_SIMPLEX, 0.42, black, 1, cv::LINE_AA);
  cv::line(canvas, {legend_x, area.y + 35}, {legend_x + 25, area.y + 35}, cv::Scalar(150, 150, 150),
           2);
  cv::putText(canvas, "oracle (by true error)", {legend_x + 30, area.y + 39},
              cv::FONT_HERSHEY_SIMPLEX, 0.42, black, 1, cv::LINE_AA);
  cv::putText(canvas,
              format("MAE, 1/m (all %.4f; ", curve.mae.front()) +
                  format("80 %% most confident %.4f, ", curve.mae_at_80) +
                  format("oracle's %.4f)", curve.oracle_at_80),
              {area.x + 5, area.y + area.height - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.42, black, 1,
              cv::LINE_AA);
  Rgb8Image out(width, height);
  std::memcpy(out.data(), canvas.data, out.size());
  return out;
}

}  // namespace omnisweep::tools
