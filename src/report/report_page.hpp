// The report page: one self-contained HTML file (inline SVG, CSS and a small script; no URL).
#pragma once

#include "accdec/taps.hpp"
#include "measure/vibration_meter.hpp"
#include "report/report_collector.hpp"

#include <map>
#include <string>

namespace gm::report {

/// What the page shows besides the collected samples.
struct PageInput {
  std::string program_name;  ///< as the run names it (file:line references use it)
  std::string machine_name, profile;
  double tau_s = 0, period_s = 0;
  bool servo = true;
  std::string summary_json;  ///< RunSummary::json(), embedded verbatim (escaped for <script>)
  std::string summary_text;  ///< RunSummary::text() and the tolerance text, shown as printed
  std::string status;        ///< "finished" or why the run did not settle
  const Taps* taps = nullptr;
  std::map<int, std::string> line_texts;  ///< source line -> its text (lines the page names)
  /// The tool tip's vibration (RunSummary::vibration(): a machine with modes), or nullptr: the
  /// page then plots tip − ref around each axis's worst stop.
  const VibrationMeter* vibration = nullptr;
};

/// The ringing plot alone (an <svg> element): tip − ref (BLU) against the time since the
/// Acc/Dec output came to rest at each axis's worst stop, one line per axis that rang; "" when
/// no axis has a recorded stop.
std::string ringing_plot(const VibrationMeter& v, const std::string& axis_letters);

/// The XY plot's view box side and margin (SVG user units): a path's larger extent spans
/// side - 2 margin units, the smaller one is centred.
inline constexpr double kXySide = 600, kXyMargin = 20;

/// The XY plot alone (an <svg> element): the programmed path (rapids dashed) and over it the
/// table's path coloured by |contour error|, with a colour legend.
std::string xy_plot(const ReportCollector& c);

/// The whole page.
std::string render_page(const ReportCollector& c, const PageInput& in);

}  // namespace gm::report
