// The report page: one self-contained HTML file (inline SVG, CSS and a small script; no URL).
#include "report/report_page.hpp"

#include "accdec/analysis.hpp"
#include "report/escape.hpp"
#include "report/page_assets.hpp"
#include "report/svg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace gm::report {
namespace {

/// |contour error| classes, low to high (the XY path's colours).
constexpr std::array<const char*, 6> kErrColours{"#2c7bb6", "#00a6ca", "#66bd63",
                                                 "#fdae61", "#f46d43", "#d7191c"};
/// Axis colours in the per-axis plots, by machine axis.
constexpr std::array<const char*, 9> kAxisColours{"#1f77b4", "#d62728", "#2ca02c",
                                                  "#9467bd", "#8c564b", "#e377c2",
                                                  "#7f7f7f", "#bcbd22", "#17becf"};

/// Lower bound of class `k` of |contour error| for a largest error `max_err`: the classes halve
/// downwards from the top ([max/2, max], [max/4, max/2), ..., [0, max/32)), so that the small
/// errors of cutting moves stay distinguishable next to a large one at a rapid.
double class_floor(std::size_t k, double max_err) {
  return k == 0 ? 0.0 : max_err / std::pow(2.0, static_cast<double>(kErrColours.size() - k));
}

int err_class(double abs_err, double max_err) {
  int c = 0;
  for (std::size_t k = 1; k < kErrColours.size(); ++k)
    if (abs_err >= class_floor(k, max_err) && max_err > 0) c = static_cast<int>(k);
  return c;
}

/// Maps mm in X and Y onto the XY view box (y up), the larger extent filling it.
struct XyMap {
  double min_x = 0, max_y = 0, s = 1, off_x = 0, off_y = 0;
  XyMap(double x0, double x1, double y0, double y1) {
    if (!(x1 >= x0) || !(y1 >= y0)) x0 = x1 = y0 = y1 = 0;  // nothing drawn
    const double inner = kXySide - 2 * kXyMargin, ext = std::max(x1 - x0, y1 - y0);
    s = ext > 0 ? inner / ext : 1.0;
    min_x = x0;
    max_y = y1;
    off_x = kXyMargin + (inner - (x1 - x0) * s) / 2;
    off_y = kXyMargin + (inner - (y1 - y0) * s) / 2;
  }
  std::pair<double, double> operator()(double x, double y) const {
    return {off_x + (x - min_x) * s, off_y + (max_y - y) * s};
  }
};

std::string num(double v) {
  return std::isfinite(v) ? fmt::format("{:.6g}", v) : "null";
}

template <typename F>
std::string json_array(std::size_t n, F&& f) {
  std::string s = "[";
  for (std::size_t i = 0; i < n; ++i) {
    if (i != 0) s += ',';
    s += f(i);
  }
  return s + "]";
}

/// Column start times, s.
std::vector<double> column_times(const ReportCollector& c) {
  std::vector<double> t;
  t.reserve(c.series().bins().size());
  for (const SeriesBin& b : c.series().bins())
    t.push_back(static_cast<double>(b.k0) * c.period_s());
  return t;
}

/// A time chart of the series `ids` (one band each, coloured `colours`), with a cursor line.
std::string time_chart(const ReportCollector& c, const std::vector<double>& t,
                       const std::vector<int>& ids, const std::vector<std::string>& colours,
                       std::string_view y_title, double height = 170) {
  const auto& bins = c.series().bins();
  double lo = 1e300, hi = -1e300;
  for (const int id : ids)
    for (const SeriesBin& b : bins) {
      lo = std::min(lo, b.lo[static_cast<std::size_t>(id)]);
      hi = std::max(hi, b.hi[static_cast<std::size_t>(id)]);
    }
  const auto [y0, y1] = padded_range(lo, hi);
  const double t0 = t.empty() ? 0.0 : t.front();
  const double t1 =
      t.empty() ? 1.0
                : std::max(t.back() + c.period_s() * static_cast<double>(c.series().width()) -
                               c.period_s(),
                           t0 + c.period_s());
  const Frame f = Frame::of(t0, t1, y0, y1, 1000, height);
  std::string s = fmt::format(
      R"(<svg class="tchart" viewBox="0 0 {} {}" data-x0="{}" data-x1="{}" data-t0="{}" data-t1="{}">)",
      coord(f.width, 0), coord(f.height, 0), coord(f.x.p0, 1), coord(f.x.p1, 1), num(t0), num(t1));
  s += f.axes("t, s", html_escape(y_title));
  for (std::size_t k = 0; k < ids.size(); ++k) {
    std::vector<double> l, h;
    l.reserve(bins.size());
    h.reserve(bins.size());
    for (const SeriesBin& b : bins) {
      l.push_back(b.lo[static_cast<std::size_t>(ids[k])]);
      h.push_back(b.hi[static_cast<std::size_t>(ids[k])]);
    }
    s += band(f, t, l, h, colours[k]);
  }
  s += fmt::format(R"(<line class="cursor" x1="0" x2="0" y1="{}" y2="{}"/></svg>)",
                   coord(f.y.p1, 1), coord(f.y.p0, 1));
  return s;
}

std::string axis_legend(const ReportCollector& c) {
  std::string s = R"(<div class="legend">)";
  const std::string letters = c.axis_letters();
  for (int a = 0; a < c.axis_count(); ++a)
    s += fmt::format(R"(<span style="background:{}"></span>{} &nbsp; )",
                     kAxisColours[static_cast<std::size_t>(a)],
                     letters[static_cast<std::size_t>(a)]);
  return s + "</div>";
}

std::string taps_section(const Taps& taps, double period_s, double tau_s) {
  std::string s;
  const std::vector<double>& b = taps.real;
  if (b.empty()) return "<p>No taps.</p>";
  const double bmax = *std::max_element(b.begin(), b.end());
  const double n = static_cast<double>(b.size());
  {
    const Frame f = Frame::of(-0.5, n - 0.5, 0.0, bmax * 1.05, 1000, 200);
    s += R"(<svg id="taps" viewBox="0 0 1000 200">)";
    s += f.axes("tap i", "b_i (real, sum 1)");
    if (b.size() <= 400) {
      const double w = std::max(0.5, (f.x(1.0) - f.x(0.0)) * 0.8);
      for (std::size_t i = 0; i < b.size(); ++i) {
        const double x = f.x(static_cast<double>(i)) - w / 2, y = f.y(b[i]);
        s += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="#1f77b4"/>)",
                         coord(x, 1), coord(y, 1), coord(w, 1), coord(f.y(0.0) - y, 1));
      }
    } else {
      std::vector<std::pair<double, double>> pts;
      for (std::size_t i = 0; i < b.size(); ++i)
        pts.emplace_back(f.x(static_cast<double>(i)), f.y(b[i]));
      s += fmt::format(R"(<polyline class="act" stroke="#1f77b4" points="{}"/>)",
                       points_attr(pts, 1));
    }
    s += "</svg>";
  }
  {
    const double nyquist = 0.5 / period_s;
    const double f_max = tau_s > 0 ? std::min(nyquist, 20.0 / tau_s) : nyquist;
    constexpr int kPoints = 500;
    std::vector<double> fr, lo, hi;
    for (int i = 0; i <= kPoints; ++i) {
      const double hz = f_max * i / kPoints;
      const double a = amplitude_response(b, 2.0 * std::numbers::pi * hz * period_s);
      const double db = std::max(-120.0, 20.0 * std::log10(std::max(a, 1e-12)));
      fr.push_back(hz);
      lo.push_back(db);
      hi.push_back(db);
    }
    const double dbmin = *std::min_element(lo.begin(), lo.end());
    const Frame f = Frame::of(0.0, f_max, std::min(-20.0, dbmin - 5.0), 5.0, 1000, 200);
    s += R"(<svg id="response" viewBox="0 0 1000 200">)";
    s += f.axes("f, Hz", "|D(e^jωT)|, dB");
    s += band(f, fr, lo, hi, "#d62728");
    s += "</svg>";
  }
  s += fmt::format(
      R"(<p class="note">{} taps (N = {}), τ = {} s, T = {} s; integer taps sum b_s = {}{}; response of the real taps up to {} Hz (Nyquist {} Hz), floor −120 dB.</p>)",
      taps.real.size(), taps.N, tau_s, period_s, taps.b_s,
      taps.integer_exact ? " (exactly proportional)" : "",
      num(tau_s > 0 ? std::min(0.5 / period_s, 20.0 / tau_s) : 0.5 / period_s),
      num(0.5 / period_s));
  return s;
}

std::string decimation_note(const ReportCollector& c) {
  const auto& sb = c.series();
  std::string s;
  if (sb.width() == 1)
    s += fmt::format("Time plots: all {} samples, one column each (not decimated). ", sb.samples());
  else
    s += fmt::format(
        "Time plots: decimated: {} samples in {} columns of {} samples; each column keeps the "
        "minimum and the maximum of every series (peaks are kept) and the source line of its "
        "largest |contour error|. ",
        sb.samples(), sb.bins().size(), sb.width());
  if (c.has_xy()) {
    const auto& pb = c.path();
    if (pb.width() == 1)
      s += "Table path: every sample. ";
    else
      s += fmt::format(
          "Table path: decimated: {} columns of {} samples, each drawn through its first sample "
          "and its sample of largest |contour error|. ",
          pb.bins().size(), pb.width());
    const PathSimplifier& p = c.programmed();
    s += fmt::format("Programmed path: {} of {} points kept", p.points().size(), p.offered());
    if (p.tolerance_mm() > 0)
      s += fmt::format(" (points closer than {} mm to the previous one dropped)",
                       num(p.tolerance_mm()));
    if (p.truncated) s += "; truncated: more separate pieces than the budget";
    s += "; arcs drawn as chords of at most 5°.";
  }
  return s;
}

}  // namespace

std::string ringing_plot(const VibrationMeter& v, const std::string& axis_letters) {
  double lo = 0, hi = 0, t0 = 0, t1 = 0;
  bool any = false;
  for (int a = 0; a < v.axes(); ++a) {
    const auto rec = v.worst_record(a);
    if (rec.empty() || !(v.axis(a).residual_blu > 0)) continue;
    any = true;
    const double rest = v.axis(a).residual_t_s;
    t0 = std::min(t0, v.worst_record_t0_s(a) - rest);
    t1 = std::max(t1,
                  v.worst_record_t0_s(a) - rest + static_cast<double>(rec.size()) * v.period_s());
    for (const double d : rec) lo = std::min(lo, d), hi = std::max(hi, d);
  }
  if (!any) return "";
  const auto [y0, y1] = padded_range(lo, hi);
  const Frame f = Frame::of(t0, t1, y0, y1, 1000, 220);
  std::string s = R"(<svg id="ringing" viewBox="0 0 1000 220">)";
  s += f.axes("t since the Acc/Dec output rests, s", "tip − ref, BLU");
  s += fmt::format(
      R"(<line x1="{0}" x2="{0}" y1="{1}" y2="{2}" stroke="#888" stroke-dasharray="4 3"/>)",
      coord(f.x(0.0), 1), coord(f.y.p1, 1), coord(f.y.p0, 1));
  for (int a = 0; a < v.axes(); ++a) {
    const auto rec = v.worst_record(a);
    if (rec.empty() || !(v.axis(a).residual_blu > 0)) continue;
    const double start = v.worst_record_t0_s(a) - v.axis(a).residual_t_s;
    std::vector<std::pair<double, double>> pts;
    pts.reserve(rec.size());
    for (std::size_t i = 0; i < rec.size(); ++i)
      pts.emplace_back(f.x(start + static_cast<double>(i) * v.period_s()), f.y(rec[i]));
    s +=
        fmt::format(R"(<polyline class="act" stroke="{}" points="{}"><title>{}</title></polyline>)",
                    kAxisColours[static_cast<std::size_t>(a)], points_attr(pts, 1),
                    a < static_cast<int>(axis_letters.size())
                        ? std::string(1, axis_letters[static_cast<std::size_t>(a)])
                        : "");
  }
  return s + "</svg>";
}

std::string xy_plot(const ReportCollector& c) {
  const PathSimplifier& prog = c.programmed();
  double x0 = prog.min_x, x1 = prog.max_x, y0 = prog.min_y, y1 = prog.max_y;
  if (prog.offered() == 0)  // no programmed motion: frame the table's path
    for (const PathBin& b : c.path().bins()) {
      x0 = std::min(x0, b.x0_mm), x1 = std::max(x1, b.x0_mm);
      y0 = std::min(y0, b.y0_mm), y1 = std::max(y1, b.y0_mm);
    }
  const XyMap map(x0, x1, y0, y1);
  std::string s = fmt::format(R"(<svg id="xy" viewBox="0 0 {0} {0}">)", coord(kXySide, 0));
  // Programmed path: one polyline per piece.
  const auto& pts = prog.points();
  for (std::size_t i = 0; i < pts.size();) {
    std::size_t j = i + 1;
    while (j < pts.size() && !pts[j].starts_piece) ++j;
    if (j - i >= 2) {
      std::vector<std::pair<double, double>> px;
      for (std::size_t k = i; k < j; ++k) px.push_back(map(pts[k].x_mm, pts[k].y_mm));
      s += fmt::format(R"(<polyline class="{}" points="{}"/>)", pts[i].rapid ? "rapid" : "prog",
                       points_attr(px));
    }
    i = j;
  }
  // Table path: runs of columns of one colour class, each run ending at the next column's start.
  const auto& bins = c.path().bins();
  const double emax = c.max_abs_contour_blu();
  for (std::size_t i = 0; i < bins.size();) {
    const int cls = err_class(bins[i].worst_abs_contour, emax);
    std::vector<std::pair<double, double>> px;
    std::size_t j = i;
    for (; j < bins.size() && err_class(bins[j].worst_abs_contour, emax) == cls; ++j) {
      px.push_back(map(bins[j].x0_mm, bins[j].y0_mm));
      if (bins[j].k_worst != bins[j].k0) px.push_back(map(bins[j].xw_mm, bins[j].yw_mm));
    }
    if (j < bins.size()) px.push_back(map(bins[j].x0_mm, bins[j].y0_mm));
    if (px.size() >= 2)
      s += fmt::format(R"(<polyline class="act" stroke="{}" points="{}"/>)",
                       kErrColours[static_cast<std::size_t>(cls)], points_attr(px));
    i = j;
  }
  s += "</svg>";
  return s;
}

std::string render_page(const ReportCollector& c, const PageInput& in) {
  std::string h;
  h.reserve(1 << 20);
  const std::string title = html_escape(in.program_name);
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">";
  h += fmt::format("<title>gmotion report: {}</title><style>{}</style></head><body>\n", title,
                   kPageStyle);
  h += fmt::format("<h1>gmotion report: {}</h1>\n", title);
  const auto& sb = c.series();
  const double duration = static_cast<double>(sb.samples()) * in.period_s;
  h += fmt::format(
      R"(<p class="meta">machine <b>{}</b>, profile <b>{}</b>, τ = {} s, T = {} s, {} taps, servo {}; {} samples ({} s); {}.</p>)",
      html_escape(in.machine_name), html_escape(in.profile), in.tau_s, in.period_s,
      in.taps != nullptr ? in.taps->real.size() : 0, in.servo ? "on" : "off", sb.samples(),
      num(duration), html_escape(in.status));
  h += fmt::format("<p class=\"note\" id=\"decimation\">{}</p>\n", html_escape(decimation_note(c)));

  // 1. The XY path.
  h += "<h2>Path in XY, coloured by |contour error|</h2>\n";
  if (c.has_xy()) {
    h += R"(<div class="xybox"><div style="flex:1 1 520px">)" + xy_plot(c) + "</div><div>";
    h +=
        R"(<p><button id="zoom-in">Zoom in</button> <button id="zoom-out">Zoom out</button> <button id="zoom-reset">Reset</button></p>)";
    h += R"(<p class="note">Wheel: zoom about the pointer; drag: pan; double click: all.</p>)";
    h += R"(<div class="legend"><p>|contour error|, BLU</p>)";
    const double emax = c.max_abs_contour_blu();
    for (std::size_t k = 0; k < kErrColours.size(); ++k) {
      const double a = class_floor(k, emax);
      const double b = k + 1 < kErrColours.size() ? class_floor(k + 1, emax) : emax;
      h += fmt::format(R"(<div><span style="background:{}"></span>{} – {}</div>)", kErrColours[k],
                       tick_label(a), tick_label(b));
    }
    h += R"(<div><span style="background:#888"></span>programmed (feed)</div>)";
    h +=
        R"(<div><span style="border-top:1px dashed #888;height:0"></span>programmed (rapid)</div>)";
    h += "</div></div></div>\n";
  } else {
    h += "<p>The machine has no X and Y axes: no XY plot.</p>\n";
  }

  // 2. Contour error and override against time, with the cursor.
  const std::vector<double> t = column_times(c);
  h += "<h2>Contour error and feed override against time</h2>\n";
  h +=
      R"(<div id="cursor-info">Move the pointer over a time plot: the time, the values and the source line under it.</div>)";
  h += time_chart(c, t, {kContourSeries}, {"#d62728"}, "contour error, BLU");
  h += time_chart(c, t, {kOverrideSeries}, {"#2ca02c"}, "feed override, %", 130);

  // 3. Per-axis velocity, acceleration and jerk.
  h += "<h2>Per-axis velocity, acceleration and jerk (Acc/Dec output)</h2>\n" + axis_legend(c);
  const std::array<const char*, 3> names{"velocity, mm/s", "acceleration, mm/s²", "jerk, mm/s³"};
  for (int q = 0; q < 3; ++q) {
    std::vector<int> ids;
    std::vector<std::string> colours;
    for (int a = 0; a < c.axis_count(); ++a) {
      ids.push_back(kFirstAxisSeries + 3 * a + q);
      colours.emplace_back(kAxisColours[static_cast<std::size_t>(a)]);
    }
    h += time_chart(c, t, ids, colours, names[static_cast<std::size_t>(q)]);
  }
  h +=
      R"(<p class="note">Finite differences of the Acc/Dec output (the commanded motion) per sample period, as the summary computes its peaks; rotary axes in degrees.</p>)";

  // 3b. The tool tip's ringing at the worst stops (a machine with modes).
  if (in.vibration != nullptr) {
    const std::string plot = ringing_plot(*in.vibration, c.axis_letters());
    h += "<h2>Tool tip ringing at the worst stop</h2>\n";
    if (plot.empty()) {
      h += "<p>The machine has structural modes, but no axis stopped with vibration.</p>\n";
    } else {
      h += axis_legend(c) + plot;
      std::string worst;
      for (int a = 0; a < in.vibration->axes(); ++a) {
        const AxisVibration& x = in.vibration->axis(a);
        if (!(x.residual_blu > 0)) continue;
        worst += fmt::format(
            "{}{}: residual vibration {:.2f} BLU after line {} (rest at {:.3f} s), "
            "settling {:.2f} BLU",
            worst.empty() ? "" : "; ", c.axis_letters()[static_cast<std::size_t>(a)],
            x.residual_blu, x.residual_line, x.residual_t_s, x.settle_blu);
      }
      h += fmt::format(
          R"(<p class="note">The tool tip (the table with its structural modes) minus the Acc/Dec output, from {} s before to {} s after the output came to rest at each axis's worst stop (the largest deflection of its modes in that window). {}.</p>)",
          num(VibrationMeter::kLeadS), num(in.vibration->window_s()), html_escape(worst));
    }
  }

  // 4. The summary.
  h += "<h2>Summary</h2>\n<table id=\"summary-table\"><tr><th>value</th><th></th></tr></table>\n";
  h += fmt::format("<pre id=\"summary-text\">{}</pre>\n", html_escape(in.summary_text));

  // 5. The Acc/Dec profile.
  h += "<h2>Acc/Dec profile: taps and frequency response</h2>\n";
  if (in.taps != nullptr) h += taps_section(*in.taps, in.period_s, in.tau_s);

  // Data for the script: the summary verbatim, the columns and the source lines they name.
  std::string summary = in.summary_json;
  while (!summary.empty() && (summary.back() == '\n' || summary.back() == ' ')) summary.pop_back();
  // The summary holds numbers, booleans and axis letters only, so no "</" can end the element.
  h += "<script type=\"application/json\" id=\"gm-summary\">" + summary + "</script>\n";
  const auto& bins = sb.bins();
  auto col = [&](int id, bool hi) {
    return json_array(bins.size(), [&](std::size_t i) {
      return num(hi ? bins[i].hi[static_cast<std::size_t>(id)]
                    : bins[i].lo[static_cast<std::size_t>(id)]);
    });
  };
  std::string src = "{";
  for (const auto& [line, text] : in.line_texts) {
    if (src.size() > 1) src += ',';
    src += fmt::format("\"{}\":{}", line, json_string(text));
  }
  src += "}";
  h += "<script type=\"application/json\" id=\"gm-data\">";
  h += fmt::format(
      R"({{"file":{},"T":{},"width":{},"t":{},"line":{},"ce_lo":{},"ce_hi":{},"ov_lo":{},"ov_hi":{},"src":{}}})",
      json_string(in.program_name), num(in.period_s), sb.width(),
      json_array(t.size(), [&](std::size_t i) { return fmt::format("{:.6f}", t[i]); }),
      json_array(bins.size(), [&](std::size_t i) { return std::to_string(bins[i].line); }),
      col(kContourSeries, false), col(kContourSeries, true), col(kOverrideSeries, false),
      col(kOverrideSeries, true), src);
  h += "</script>\n<script>";
  h += kPageScript;
  h += "</script>\n</body></html>\n";
  return h;
}

}  // namespace gm::report
