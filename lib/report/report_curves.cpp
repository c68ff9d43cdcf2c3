// Curve plots of the HTML report (report/report.hpp): inline SVG, one polyline
// per curve and side with one vertex per setpoint, each vertex marked (SVG
// markers: no element per setpoint, so 100 curves of 1,000 setpoints stay a
// few hundred kB). Axes in the curve's own units: X in ms over the curve's
// length when X is time (else the setpoint number), Y in mm when the Y
// dimension is 0.1 um (code 5), else in the curve's raw unit named by its
// dimension code.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "report/report.hpp"
#include "report/report_parts.hpp"

namespace lmcfg::report::parts {
namespace {

// Plot area inside the figure's SVG (px), and the data coordinates' scale:
// 10 units per px, so integer coordinates are 0.1 px exact.
constexpr int kLeft = 84, kTop = 12, kWidth = 720, kHeight = 240, kDeltaHeight = 110;
constexpr int kUnits = 10;

struct Axis {
  double lo = 0, hi = 1, step = 1;
  int decimals = 0;
  std::string label;
};

std::string num(double v, int decimals) {
  char b[48];
  if (std::fabs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0;  // no "-0"
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

// A range widened to round ticks (1, 2, 5 x 10^k), about five of them.
Axis nice_axis(double lo, double hi, std::string label) {
  Axis a;
  a.label = std::move(label);
  if (!(hi > lo)) {
    const double pad = lo == 0 ? 1 : std::fabs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  if (!(hi > lo) || !std::isfinite(hi - lo)) lo = 0, hi = 1;  // nothing to show
  const double raw = (hi - lo) / 5;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  a.step = step;
  a.lo = std::floor(lo / step + 1e-9) * step;
  a.hi = std::ceil(hi / step - 1e-9) * step;
  a.decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  return a;
}

// What a curve's setpoints mean on the plot's axes.
struct Series {
  const config::Curve* curve = nullptr;
  std::optional<config::CurveView> view;
  std::string error;         // why it cannot be plotted ("" = it can)
  std::vector<double> x, y;  // in axis units
  std::string x_label, y_label;
};

Series series(const config::Curve& c) {
  Series s;
  s.curve = &c;
  auto v = config::decode_curve(c);
  if (!v.ok()) {
    s.error = v.error().message;
    return s;
  }
  s.view = *v;
  const auto& cv = *s.view;
  if (cv.setpoints.size() != cv.setpoint_count) {
    s.error = std::to_string(cv.bytes_per_setpoint) + " bytes per setpoint: not plotted";
    return s;
  }
  const std::size_t n = cv.setpoints.size();
  const bool time = cv.x_code == 0;
  const double length_ms = cv.length / 100.0;
  s.x_label =
      time ? "time [ms]"
           : "setpoint number (X: " + std::string(config::CurveView::x_name(cv.x_code)) + ")";
  double yscale = 1;
  const std::string yname(config::CurveView::y_name(cv.y_code));
  if (cv.y_dimension == 5) {
    yscale = 1e-4;  // 0.1 um -> mm
    s.y_label = yname + " [mm]";
  } else {
    s.y_label = yname + " [dimension code " + std::to_string(cv.y_dimension) + "]";
  }
  s.x.reserve(n);
  s.y.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (time)
      s.x.push_back(n > 1 ? length_ms * static_cast<double>(i) / static_cast<double>(n - 1) : 0);
    else
      s.x.push_back(static_cast<double>(i + 1));
    s.y.push_back(cv.setpoints[i] * yscale);
  }
  return s;
}

void append_int(std::string& out, long v) {
  char b[24];
  const int len = std::snprintf(b, sizeof b, "%ld", v);
  out.append(b, static_cast<std::size_t>(len));
}

// Axes, grid and tick labels of a plot area at (kLeft, top) of height h.
void axes(std::string& out, const Axis& ax, const Axis& ay, int top, int h, bool x_labels) {
  out += "<g class=\"grid\">";
  for (double t = ax.lo; t <= ax.hi + ax.step * 1e-6; t += ax.step) {
    const double px = kLeft + (t - ax.lo) / (ax.hi - ax.lo) * kWidth;
    out += "<line x1=\"" + num(px, 1) + "\" y1=\"" + std::to_string(top) + "\" x2=\"" + num(px, 1) +
           "\" y2=\"" + std::to_string(top + h) + "\"/>";
    if (x_labels)
      out += "<text class=\"tx\" x=\"" + num(px, 1) + "\" y=\"" + std::to_string(top + h + 16) +
             "\">" + num(t, ax.decimals) + "</text>";
  }
  for (double t = ay.lo; t <= ay.hi + ay.step * 1e-6; t += ay.step) {
    const double py = top + (1 - (t - ay.lo) / (ay.hi - ay.lo)) * h;
    out += "<line x1=\"" + std::to_string(kLeft) + "\" y1=\"" + num(py, 1) + "\" x2=\"" +
           std::to_string(kLeft + kWidth) + "\" y2=\"" + num(py, 1) + "\"/>";
    out += "<text class=\"ty\" x=\"" + std::to_string(kLeft - 6) + "\" y=\"" + num(py + 4, 1) +
           "\">" + num(t, ay.decimals) + "</text>";
  }
  out += "</g><rect class=\"frame\" x=\"" + std::to_string(kLeft) + "\" y=\"" +
         std::to_string(top) + "\" width=\"" + std::to_string(kWidth) + "\" height=\"" +
         std::to_string(h) + "\"/>";
  if (x_labels)
    out += "<text class=\"xl\" x=\"" + std::to_string(kLeft + kWidth / 2) + "\" y=\"" +
           std::to_string(top + h + 34) + "\">" + html_escape(ax.label) + "</text>";
  out += "<text class=\"yl\" transform=\"translate(14 " + std::to_string(top + h / 2) +
         ") rotate(-90)\">" + html_escape(ay.label) + "</text>";
}

// The nested data SVG of a plot area: integer coordinates, kUnits per px.
void open_data(std::string& out, int top, int h) {
  out += "<svg x=\"" + std::to_string(kLeft) + "\" y=\"" + std::to_string(top) + "\" width=\"" +
         std::to_string(kWidth) + "\" height=\"" + std::to_string(h) + "\" viewBox=\"0 0 " +
         std::to_string(kWidth * kUnits) + " " + std::to_string(h * kUnits) +
         "\" overflow=\"visible\">";
}

void polyline(std::string& out, const std::vector<double>& x, const std::vector<double>& y,
              const Axis& ax, const Axis& ay, int h, const char* cls, const char* side) {
  out += "<polyline class=\"";
  out += cls;
  out += "\"";
  if (*side) {
    out += " data-side=\"";
    out += side;
    out += "\" data-setpoints=\"" + std::to_string(x.size()) + "\"";
    for (const char* where : {"start", "mid", "end"}) {
      out += " marker-";
      out += where;
      out += "=\"url(#m";
      out += side;
      out += ")\"";
    }
  }
  out += " points=\"";
  const double sx = kWidth * kUnits / (ax.hi - ax.lo), sy = h * kUnits / (ay.hi - ay.lo);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i) out += ' ';
    append_int(out, std::lround((x[i] - ax.lo) * sx));
    out += ',';
    append_int(out, std::lround((ay.hi - y[i]) * sy));
  }
  out += "\"/>";
}

std::pair<double, double> range_of(const std::vector<double>& v, std::pair<double, double> r) {
  for (double d : v) r = {std::min(r.first, d), std::max(r.second, d)};
  return r;
}

constexpr std::pair<double, double> kEmpty{1e300, -1e300};

// One plot of one or two series (A blue, B orange); `delta` adds B - A below.
void plot(std::string& out, const Series* a, const Series* b, bool delta) {
  const Series* first = a ? a : b;
  auto xr = kEmpty, yr = kEmpty;
  for (const Series* s : {a, b}) {
    if (!s) continue;
    xr = range_of(s->x, xr);
    yr = range_of(s->y, yr);
  }
  if (xr.first > xr.second) xr = yr = {0, 1};
  const Axis ax = nice_axis(xr.first, xr.second, first->x_label);
  const Axis ay = nice_axis(yr.first, yr.second, first->y_label);
  std::vector<double> d;
  if (delta)
    for (std::size_t i = 0; i < a->y.size(); ++i) d.push_back(b->y[i] - a->y[i]);
  const int dtop = kTop + kHeight + 18;
  const int total = kTop + kHeight + 42 + (delta ? kDeltaHeight + 26 : 0);
  out += "<svg class=\"plot\" viewBox=\"0 0 " + std::to_string(kLeft + kWidth + 12) + " " +
         std::to_string(total) + "\" role=\"img\" aria-label=\"" + html_escape(ay.label) +
         " over " + html_escape(ax.label) + "\">";
  axes(out, ax, ay, kTop, kHeight, !delta);
  open_data(out, kTop, kHeight);
  if (a) polyline(out, a->x, a->y, ax, ay, kHeight, "setpoints a", "a");
  if (b) polyline(out, b->x, b->y, ax, ay, kHeight, "setpoints b", "b");
  out += "</svg>";
  if (delta) {
    auto dr = range_of(d, kEmpty);
    Axis dy = nice_axis(dr.first, dr.second, "B - A");
    axes(out, ax, dy, dtop, kDeltaHeight, true);
    open_data(out, dtop, kDeltaHeight);
    polyline(out, a->x, d, ax, dy, kDeltaHeight, "delta", "");
    out += "</svg>";
  }
  out += "</svg>";
}

std::string title(std::uint32_t id, const Series& s) {
  std::string t = "Curve " + std::to_string(id);
  if (s.view && !s.view->name.empty())
    t += " \xE2\x80\x9C" + html_escape(s.view->name) + "\xE2\x80\x9D";
  return t;
}

// The decoded info block as rows of (field, value).
std::vector<std::pair<std::string, std::string>> info_rows(const Series& s) {
  std::vector<std::pair<std::string, std::string>> r;
  const auto& c = *s.curve;
  if (!s.view) {
    r.push_back({"blocks", std::to_string(c.info.size()) + " B info, " +
                               std::to_string(c.data.size()) + " B data"});
    return r;
  }
  const auto& v = *s.view;
  char hex[16];
  std::snprintf(hex, sizeof hex, "%04Xh", v.object_type);
  r.push_back({"name", v.name});
  r.push_back({"curve ID (info)", std::to_string(v.curve_id)});
  r.push_back({"type", std::string(hex) + ": " + std::string(config::CurveView::y_name(v.y_code)) +
                           " over " + std::string(config::CurveView::x_name(v.x_code))});
  r.push_back({"setpoints", std::to_string(v.setpoint_count) + " \xC3\x97 " +
                                std::to_string(v.bytes_per_setpoint) + " B"});
  r.push_back({"length", v.length_ms_text() + " ms (" + std::to_string(v.length) +
                             " \xC3\x97 10 \xC2\xB5s)"});
  r.push_back(
      {"X dimension", std::to_string(v.x_dimension) + (v.x_dimension == 0x1A ? " (0.01 ms)" : "")});
  r.push_back({"Y dimension",
               std::to_string(v.y_dimension) + (v.y_dimension == 5 ? " (0.1 \xC2\xB5m)" : "")});
  r.push_back({"wizard", std::to_string(v.wizard)});
  for (std::size_t i = 0; i < v.wizard_params.size(); ++i)
    r.push_back({"wizard parameter " + std::to_string(i + 1), std::to_string(v.wizard_params[i])});
  return r;
}

void figure_open(std::string& out, std::uint32_t id, const std::string& cls,
                 const std::string& attrs) {
  out += "<figure class=\"curve" + cls + "\" id=\"curve-" + std::to_string(id) +
         "\" data-curve-id=\"" + std::to_string(id) + "\"" + attrs + ">";
}

}  // namespace

std::string curve_defs() {
  // Markers of userSpaceOnUse size in the data coordinates (kUnits per px).
  std::string m;
  for (const auto& [side, colour] : {std::pair{"a", "#1f5fbf"}, std::pair{"b", "#d9480f"}}) {
    m += "<marker id=\"m";
    m += side;
    m += "\" viewBox=\"0 0 10 10\" refX=\"5\" refY=\"5\" markerUnits=\"userSpaceOnUse\" "
         "markerWidth=\"50\" markerHeight=\"50\"><circle cx=\"5\" cy=\"5\" r=\"4\" fill=\"";
    m += colour;
    m += "\"/></marker>";
  }
  return "<svg class=\"defs\" width=\"0\" height=\"0\" aria-hidden=\"true\"><defs>" + m +
         "</defs></svg>\n";
}

void curve_figure(std::string& out, const config::Curve& c) {
  const Series s = series(c);
  figure_open(out, c.id, "", "");
  out += "<figcaption>" + title(c.id, s) + "</figcaption><div class=\"fig\">";
  if (s.error.empty())
    plot(out, &s, nullptr, false);
  else
    out += "<p class=\"bad\">not plotted: " + html_escape(s.error) + "</p>";
  out += "<table class=\"info\">";
  for (const auto& [k, v] : info_rows(s))
    out += "<tr><th>" + html_escape(k) + "</th><td>" + html_escape(v) + "</td></tr>";
  out += "</table></div></figure>\n";
}

void curve_figure_diff(std::string& out, const config::Curve* a, const config::Curve* b,
                       const DiffItem* item) {
  std::optional<Series> sa, sb;
  if (a) sa = series(*a);
  if (b) sb = series(*b);
  const std::uint32_t id = a ? a->id : b->id;
  std::string cls, attrs;
  if (item) {
    cls = std::string(" diff ") + (!a ? "added" : !b ? "removed" : "changed");
    attrs = diff_key(*item);
  }
  figure_open(out, id, cls, attrs);
  out += "<figcaption>" + title(id, sa ? *sa : *sb);
  if (item)
    out += " <span class=\"tag\">" +
           std::string(!a   ? "added"
                       : !b ? "removed"
                            : "changed") +
           "</span>";
  out += "</figcaption>";
  if (item && !item->detail.empty())
    out += "<p class=\"detail\">" + html_escape(item->detail) + "</p>";
  out += "<div class=\"fig\">";
  const bool pa = sa && sa->error.empty(), pb = sb && sb->error.empty();
  const bool overlay = item && pa && pb;
  if (pa || pb) {
    const bool delta = overlay && sa->y.size() == sb->y.size() && !sa->y.empty();
    out += "<div>";
    // Unchanged: one plot (side A); changed: both sides overlaid.
    plot(out, pa ? &*sa : nullptr, pb && (overlay || !pa) ? &*sb : nullptr, delta);
    if (overlay) {
      out +=
          "<p class=\"legend\"><span class=\"ka\">A</span> side A &nbsp; <span "
          "class=\"kb\">B</span> side B";
      if (delta)
        out += " &nbsp; below: B \xE2\x88\x92 A per setpoint";
      else
        out += " &nbsp; (setpoint counts differ: no per-setpoint difference)";
      out += "</p>";
    }
    out += "</div>";
  }
  for (const auto* s : {sa ? &*sa : nullptr, sb ? &*sb : nullptr})
    if (s && !s->error.empty())
      out += "<p class=\"bad\">not plotted: " + html_escape(s->error) + "</p>";
  // Info block side by side, differing fields marked.
  std::vector<std::pair<std::string, std::string>> ra, rb;
  if (sa) ra = info_rows(*sa);
  if (sb) rb = info_rows(*sb);
  out += "<table class=\"info\"><tr><th></th><th>A</th><th>B</th></tr>";
  const std::size_t n = std::max(ra.size(), rb.size());
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& key = i < ra.size() ? ra[i].first : rb[i].first;
    const std::string va = i < ra.size() ? ra[i].second : (sa ? "" : "absent");
    const std::string vb = i < rb.size() ? rb[i].second : (sb ? "" : "absent");
    out += std::string("<tr") + (va != vb ? " class=\"chg\"" : "") + "><th>" + html_escape(key) +
           "</th><td>" + html_escape(va) + "</td><td>" + html_escape(vb) + "</td></tr>";
  }
  out += "</table></div></figure>\n";
}

}  // namespace lmcfg::report::parts
