// The trace schema: columns, units and formats, from trace_columns.def (the one definition).
#pragma once

#include "common/axis.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// How a column's value is written (see trace_columns.def).
enum class TraceKind { Time, Line, Count, Fixed3, Percent };
/// Where a column sits in a row: before the axes, once per axis, after the axes.
enum class TraceSection { Head, Axis, Tail };
/// The optional column sets (trace_columns.def's WHEN), as bits of a trace's column set; a
/// column of set `when` is in a trace whose set holds all of its bits (`always`: none).
using TraceColumnSet = unsigned;
inline constexpr TraceColumnSet kTraceAlways = 0;
/// The machine has structural modes: the tool tip per axis.
inline constexpr TraceColumnSet kTraceModes = 1;

struct TraceColumn {
  TraceSection section;
  std::string_view name;  ///< for axis columns, the part after "x_"
  TraceKind kind;
  std::string_view unit;
  double csv_resolution;
  TraceColumnSet when;  ///< the optional set the column belongs to (kTraceAlways: every trace)
  /// In a trace of column set `set`.
  constexpr bool in(TraceColumnSet set) const { return (when & set) == when; }
};

/// The spellings trace_columns.def uses for sections and kinds.
namespace trace_def {
inline constexpr TraceSection head = TraceSection::Head, axis = TraceSection::Axis,
                              tail = TraceSection::Tail;
inline constexpr TraceKind time = TraceKind::Time, line = TraceKind::Line, count = TraceKind::Count,
                           fixed3 = TraceKind::Fixed3, percent = TraceKind::Percent;
inline constexpr TraceColumnSet always = kTraceAlways, modes = kTraceModes;
}  // namespace trace_def

/// Every column of the schema, in row order (axis columns once, for the axis block).
inline constexpr std::array kTraceColumns{
#define GM_TRACE_COLUMN(section, name, kind, value, unit, res, when) \
  TraceColumn{trace_def::section, #name, trace_def::kind, unit, res, trace_def::when},
#include "trace/trace_columns.def"
#undef GM_TRACE_COLUMN
};

/// trace_columns.def lists the head columns, then the axis columns, then the tail columns.
constexpr bool trace_sections_in_order() {
  for (std::size_t i = 1; i < kTraceColumns.size(); ++i)
    if (kTraceColumns[i].section < kTraceColumns[i - 1].section) return false;
  return true;
}
static_assert(trace_sections_in_order(), "trace_columns.def: head, then axis, then tail columns");

/// Bytes of a column's binary field.
constexpr std::size_t trace_binary_bytes(TraceKind k) {
  return k == TraceKind::Line ? 4 : 8;
}

/// The column names of a trace of these axes ("t_s", "line", "x_cmd", ...) and column set, in
/// row order.
std::vector<std::string> trace_column_names(std::string_view axis_letters,
                                            TraceColumnSet set = kTraceAlways);
/// The `# units:` header text after "# units: " (the columns of the set).
std::string trace_units_text(TraceColumnSet set = kTraceAlways);
/// The schema column of a trace column name ("x_cmd" -> the axis column "cmd"), or nullptr.
const TraceColumn* find_trace_column(std::string_view column_name);

}  // namespace gm
