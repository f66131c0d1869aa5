// The interpreter's start from the persistent parameters of a .var file (LinuxCNC Interp::init).
#include "interp/frame.hpp"
#include "interp/interpreter.hpp"

namespace gm {

void Interpreter::restore_system_parameters(const std::function<double(int)>& par) {
  int index = static_cast<int>(par(5220) + 0.0001);  // 1 = G54 .. 9 = G59.3
  if (index < 1 || index > 9) index = 1;
  for (int i = 0; i < 9; ++i) {
    tables_.g28_mm[i] = par(5161 + i);
    tables_.g30_mm[i] = par(5181 + i);
    tables_.g92_saved_mm[i] = par(5211 + i);
    for (int k = 0; k < 9; ++k)
      tables_.g5x_mm[static_cast<std::size_t>(k)][i] = par(5221 + 20 * k + i);
  }
  for (int k = 0; k < 9; ++k)
    tables_.g5x_rotation_deg[static_cast<std::size_t>(k)] = par(5230 + 20 * k);
  // #5210: G92 was in effect when the file was written, so its offsets apply again.
  ModalState& st = state_mut();
  select_coord_system(st, tables_, index - 1);
  st.g92_flag = par(5210);  // kept as read: a 2 reads back as 2 (rs274)
  st.g92_applied = st.g92_flag != 0.0;
  st.g92_mm = st.g92_applied ? tables_.g92_saved_mm : Pos9::Zero();
  ++tables_version_;
}

}  // namespace gm

namespace gm {

bool Interpreter::write_system_parameter(int n, double v) {
  auto in = [n](int first) { return n >= first && n < first + 9; };
  const auto i = [n](int first) { return n - first; };
  if (in(5161)) {
    tables_.g28_mm[i(5161)] = v;
  } else if (in(5181)) {
    tables_.g30_mm[i(5181)] = v;
  } else if (in(5211)) {
    tables_.g92_saved_mm[i(5211)] = v;
  } else if (n >= 5221 && n <= 5390 && (n - 5221) % 20 < 10) {
    const auto k = static_cast<std::size_t>((n - 5221) / 20);
    const int axis = (n - 5221) % 20;
    if (axis == 9)
      tables_.g5x_rotation_deg[k] = v;
    else
      tables_.g5x_mm[k][axis] = v;
  } else {
    return false;
  }
  ++tables_version_;
  return true;
}

}  // namespace gm
