// Instruction-set choice for the block kernels: CPU check once, GMOTION_ISA may lower it.
#include "common/isa.hpp"

#include <cstdlib>
#include <string_view>

namespace gm {

namespace {

Isa cpu_best() {
#if defined(__x86_64__) || defined(__i386__)
  // An explicit check rather than an ifunc (target_clones), whose resolver runs before the
  // sanitizers' runtimes are up.
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512vl"))
    return Isa::Avx512;
  if (__builtin_cpu_supports("avx2")) return Isa::Avx2;
#endif
  return Isa::Portable;
}

Isa choose() {
  const Isa best = cpu_best();
  const char* env = std::getenv("GMOTION_ISA");
  if (env == nullptr) return best;
  const std::string_view want(env);
  const Isa asked = want == "portable" ? Isa::Portable
                    : want == "avx2"   ? Isa::Avx2
                                       : Isa::Avx512;  // anything else: no lowering
  return static_cast<int>(asked) < static_cast<int>(best) ? asked : best;
}

}  // namespace

Isa active_isa() {
  static const Isa isa = choose();
  return isa;
}

const char* isa_name(Isa isa) {
  switch (isa) {
    case Isa::Avx2:
      return "avx2";
    case Isa::Avx512:
      return "avx512";
    default:
      return "portable";
  }
}

}  // namespace gm
