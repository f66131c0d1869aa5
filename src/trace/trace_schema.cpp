// The trace schema's names and units text (the columns themselves are in trace_columns.def).
#include "trace/trace_schema.hpp"

namespace gm {

namespace {

char lower(char c) {
  return static_cast<char>(c - 'A' + 'a');
}

}  // namespace

std::vector<std::string> trace_column_names(std::string_view axis_letters, TraceColumnSet set) {
  std::vector<std::string> names;
  for (TraceSection section : {TraceSection::Head, TraceSection::Axis, TraceSection::Tail}) {
    if (section == TraceSection::Axis) {
      for (char a : axis_letters)
        for (const TraceColumn& c : kTraceColumns)
          if (c.section == section && c.in(set))
            names.push_back(std::string(1, lower(a)) + "_" + std::string(c.name));
    } else {
      for (const TraceColumn& c : kTraceColumns)
        if (c.section == section && c.in(set)) names.emplace_back(c.name);
    }
  }
  return names;
}

std::string trace_units_text(TraceColumnSet set) {
  std::string out;
  for (const TraceColumn& c : kTraceColumns) {
    if (!c.in(set)) continue;
    if (!out.empty()) out += "; ";
    if (c.section == TraceSection::Axis) out += "*_";
    out += c.name;
    out += ' ';
    out += c.unit;
  }
  return out;
}

const TraceColumn* find_trace_column(std::string_view column_name) {
  for (const TraceColumn& c : kTraceColumns) {
    if (c.section != TraceSection::Axis) {
      if (column_name == c.name) return &c;
    } else if (column_name.size() == c.name.size() + 2 && column_name[1] == '_' &&
               column_name.substr(2) == c.name) {
      return &c;
    }
  }
  return nullptr;
}

}  // namespace gm
