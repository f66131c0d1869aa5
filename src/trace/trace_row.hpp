// One trace row's values in schema order (from trace_columns.def), for the writers.
#pragma once

#include "common/axis.hpp"
#include "motion/sample_record.hpp"
#include "trace/trace_schema.hpp"

#include <type_traits>

namespace gm {

/// Calls f(kind, value) for every column of sample `s` in row order: the head columns, the axis
/// columns for each of the first `axes` axes (the machine's, in its order), the tail columns;
/// only the columns of column set `Set` (trace_schema.hpp; a compile-time choice, no branch).
/// `kind` is a std::integral_constant<TraceKind, ...>, so a writer picks the format at compile time
/// and the row costs no per-column branch. `s` is a SampleRecord or anything with its field names
/// (BlockRow); `axes` an int or, for a loop the compiler unrolls, std::integral_constant<int, N>.
template <TraceColumnSet Set = kTraceAlways, typename Row, typename Axes, typename F>
inline void visit_trace_row(const Row& s, Axes axes, F&& f) {
#define GM_TRACE_COLUMN(section, name, kind, value, unit, res, when) \
  if constexpr ((trace_def::when & Set) == trace_def::when) {        \
    GM_TRACE_VISIT_##section(kind, value)                            \
  }
#define GM_TRACE_CALL(kind, value) f(std::integral_constant<TraceKind, trace_def::kind>{}, value);
#define GM_TRACE_VISIT_head(kind, value) GM_TRACE_CALL(kind, value)
#define GM_TRACE_VISIT_axis(kind, value)
#define GM_TRACE_VISIT_tail(kind, value)
#include "trace/trace_columns.def"
#undef GM_TRACE_VISIT_head
#undef GM_TRACE_VISIT_axis
#define GM_TRACE_VISIT_head(kind, value)
#define GM_TRACE_VISIT_axis(kind, value) GM_TRACE_CALL(kind, value)
  for (int a = 0; a < static_cast<int>(axes); ++a) {
#include "trace/trace_columns.def"
  }
#undef GM_TRACE_VISIT_axis
#undef GM_TRACE_VISIT_tail
#define GM_TRACE_VISIT_axis(kind, value)
#define GM_TRACE_VISIT_tail(kind, value) GM_TRACE_CALL(kind, value)
#include "trace/trace_columns.def"
#undef GM_TRACE_VISIT_head
#undef GM_TRACE_VISIT_axis
#undef GM_TRACE_VISIT_tail
#undef GM_TRACE_CALL
#undef GM_TRACE_COLUMN
}

}  // namespace gm
