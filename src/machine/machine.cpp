// The built-in default machine: the paper's numbers, with the paper's own y plant and gains.
#include "machine/machine.hpp"

namespace gm {

Machine default_machine() {
  Machine m;
  m.name = "default";
  m.source = "<built-in>";
  AxisConfig& y = m.axes[static_cast<std::size_t>(Axis::Y)];
  y.plant_num = {32.07};
  y.plant_den = {1.0, 13.823};
  y.kvp = 0.0442;
  y.kvi = 0.0098;
  return m;
}

}  // namespace gm
