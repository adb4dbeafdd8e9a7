#include "hydrolux/io/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hydrolux/core/error.hpp"

namespace hydrolux::io {

namespace {

std::string escape_xml(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Decimal places that show a tick spacing exactly (0.05 -> 2, 10 -> 0).
int decimals_for(double step) {
  int d = 0;
  while (d < 8 && std::fabs(step * std::pow(10.0, d) - std::round(step * std::pow(10.0, d))) > 1e-9) ++d;
  return d;
}

std::vector<double> ticks(double lo, double hi, double step) {
  std::vector<double> t;
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (int i = 0;; ++i) {
    const double v = first + i * step;
    if (v > hi + 1e-9 * step) break;
    t.push_back(v);
  }
  return t;
}

}  // namespace

std::string render_svg(const Plot& p) {
  if (!(p.x_max > p.x_min) || !(p.y_max > p.y_min))
    throw Error(fmt::format("plot '{}': empty axis range", p.title));
  if (!(p.x_tick > 0) || !(p.y_tick > 0))
    throw Error(fmt::format("plot '{}': tick spacing must be > 0", p.title));
  if (p.y_log && !(p.y_min > 0))
    throw Error(fmt::format("plot '{}': a logarithmic axis needs y_min > 0", p.title));
  for (const auto& s : p.series)
    if (s.x.size() != s.y.size())
      throw Error(fmt::format("plot '{}': series '{}' has {} x and {} y values", p.title, s.label,
                              s.x.size(), s.y.size()));

  const double left = 72, right = 24, top = 48, bottom = 58;
  const double pw = p.width - left - right, ph = p.height - top - bottom;
  const auto sx = [&](double x) { return left + (x - p.x_min) / (p.x_max - p.x_min) * pw; };
  const double y_lo = p.y_log ? std::log10(p.y_min) : p.y_min;
  const double y_hi = p.y_log ? std::log10(p.y_max) : p.y_max;
  const auto sy = [&](double y) {
    const double v = p.y_log ? std::log10(y) : y;
    return top + (1 - (v - y_lo) / (y_hi - y_lo)) * ph;
  };

  std::string o;
  o += fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n",
      p.width, p.height);
  o += fmt::format("<rect width=\"{}\" height=\"{}\" fill=\"white\"/>\n", p.width, p.height);
  o += fmt::format("<defs><clipPath id=\"plot-area\"><rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" "
                   "height=\"{:.2f}\"/></clipPath></defs>\n",
                   left, top, pw, ph);
  o += fmt::format("<text x=\"{:.1f}\" y=\"28\" font-size=\"17\" text-anchor=\"middle\" "
                   "font-weight=\"bold\">{}</text>\n",
                   left + pw / 2, escape_xml(p.title));

  // Grid and tick labels.
  const int xd = decimals_for(p.x_tick), yd = decimals_for(p.y_tick);
  for (double x : ticks(p.x_min, p.x_max, p.x_tick)) {
    o += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"#e3e3e3\"/>\n",
                     sx(x), top, top + ph);
    o += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"12\" text-anchor=\"middle\">{:.{}f}</text>\n",
                     sx(x), top + ph + 18, x, xd);
  }
  if (p.y_log) {
    for (int e = int(std::ceil(y_lo - 1e-9)); e <= int(std::floor(y_hi + 1e-9)); ++e) {
      const double y = std::pow(10.0, e);
      o += fmt::format("<line x1=\"{1:.2f}\" y1=\"{0:.2f}\" x2=\"{2:.2f}\" y2=\"{0:.2f}\" stroke=\"#e3e3e3\"/>\n",
                       sy(y), left, left + pw);
      const std::string label = e >= -2 && e <= 3 ? fmt::format("{:g}", y) : fmt::format("1e{}", e);
      o += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"12\" text-anchor=\"end\">{}</text>\n",
                       left - 8, sy(y) + 4, label);
    }
  } else {
    for (double y : ticks(p.y_min, p.y_max, p.y_tick)) {
      o += fmt::format("<line x1=\"{1:.2f}\" y1=\"{0:.2f}\" x2=\"{2:.2f}\" y2=\"{0:.2f}\" stroke=\"#e3e3e3\"/>\n",
                       sy(y), left, left + pw);
      o += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"12\" text-anchor=\"end\">{:.{}f}</text>\n",
                       left - 8, sy(y) + 4, y, yd);
    }
  }
  o += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"none\" "
                   "stroke=\"#333\"/>\n",
                   left, top, pw, ph);
  o += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"14\" text-anchor=\"middle\">{}</text>\n",
                   left + pw / 2, p.height - 14.0, escape_xml(p.x_label));
  o += fmt::format("<text transform=\"translate(18 {:.2f}) rotate(-90)\" font-size=\"14\" "
                   "text-anchor=\"middle\">{}</text>\n",
                   top + ph / 2, escape_xml(p.y_label));

  // Markers, then series, clipped to the plot area.
  for (const auto& m : p.markers) {
    if (!(m.x >= p.x_min && m.x <= p.x_max)) continue;  // also skips NaN
    o += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"{3}\" "
                     "stroke-dasharray=\"2 3\"/>\n",
                     sx(m.x), top, top + ph, m.color);
    o += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"11\" fill=\"{}\" text-anchor=\"end\" "
                     "transform=\"rotate(-90 {:.2f} {:.2f})\">{}</text>\n",
                     sx(m.x) - 4, top + 6, m.color, sx(m.x) - 4, top + 6, escape_xml(m.label));
  }
  o += "<g clip-path=\"url(#plot-area)\" fill=\"none\" stroke-width=\"2\" stroke-linejoin=\"round\">\n";
  for (const auto& s : p.series) {
    if (s.x.empty()) continue;
    o += fmt::format("<polyline stroke=\"{}\"{} points=\"", s.color,
                     s.dashed ? " stroke-dasharray=\"7 4\"" : "");
    bool first = true;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (p.y_log && !(s.y[i] > 0))) continue;
      // Clamp far-off-scale points so the polyline stays within sane coordinates (it is clipped).
      const double py = std::clamp(sy(s.y[i]), top - 4 * ph, top + 5 * ph);
      o += fmt::format("{}{:.2f},{:.2f}", first ? "" : " ", sx(s.x[i]), py);
      first = false;
    }
    o += "\"/>\n";
  }
  o += "</g>\n";

  // Legend.
  std::size_t longest = 0;
  for (const auto& s : p.series) longest = std::max(longest, s.label.size());
  const double lw = 46 + 7.2 * double(longest), lh = 8 + 20.0 * double(p.series.size());
  const bool at_right = p.legend == LegendCorner::TopRight || p.legend == LegendCorner::CenterRight ||
                        p.legend == LegendCorner::BottomRight;
  const bool at_bottom = p.legend == LegendCorner::BottomLeft || p.legend == LegendCorner::BottomRight;
  const double lx = at_right ? left + pw - lw - 10 : left + 10;
  const bool centred = p.legend == LegendCorner::CenterLeft || p.legend == LegendCorner::CenterRight;
  const double ly = centred ? top + (ph - lh) / 2
                    : at_bottom ? top + ph - lh - 10
                                : top + 10;
  if (!p.series.empty()) {
    o += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"white\" "
                     "fill-opacity=\"0.9\" stroke=\"#999\"/>\n",
                     lx, ly, lw, lh);
    for (std::size_t i = 0; i < p.series.size(); ++i) {
      const auto& s = p.series[i];
      const double y = ly + 14 + 20.0 * double(i);
      o += fmt::format("<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" "
                       "stroke-width=\"2\"{}/>\n",
                       lx + 8, y, lx + 36, y, s.color, s.dashed ? " stroke-dasharray=\"7 4\"" : "");
      o += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"12\">{}</text>\n", lx + 42, y + 4,
                       escape_xml(s.label));
    }
  }
  o += "</svg>\n";
  return o;
}

}  // namespace hydrolux::io
