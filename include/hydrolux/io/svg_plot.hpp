#pragma once
// Line plots as standalone SVG text: axes with ticks and labels, a title, a legend, optional
// vertical markers (e.g. Brewster's angle). Dependency-free, deterministic output.
#include <string>
#include <vector>

namespace hydrolux::io {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  std::string color = "#1f77b4";
  bool dashed = false;
};

struct PlotMarker {  // a labelled vertical line at x
  double x = 0;
  std::string label;
  std::string color = "#777777";
};

enum class LegendCorner { TopLeft, TopRight, CenterLeft, CenterRight, BottomLeft, BottomRight };

struct Plot {
  std::string title;
  std::string x_label, y_label;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  double x_tick = 0.1, y_tick = 0.1;  // spacing of ticks and grid lines (y_tick unused when y_log)
  // Logarithmic y axis: y_min, y_max > 0; ticks and labels at the powers of ten; points with
  // y <= 0 are left out of their polyline.
  bool y_log = false;
  std::vector<PlotSeries> series;
  std::vector<PlotMarker> markers;
  LegendCorner legend = LegendCorner::TopLeft;
  int width = 720, height = 460;  // pixels
};

// The plot as an SVG document. Throws hydrolux::Error for an empty or inverted axis range, a
// non-positive tick spacing, or a series whose x and y differ in length.
std::string render_svg(const Plot& plot);

}  // namespace hydrolux::io
