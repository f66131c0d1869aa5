// Which vector instruction set the block kernels run: chosen once per process from the CPU.
#pragma once

namespace gm {

/// The instruction sets the block kernels are compiled for. The shipped build is -O2 without
/// -march, so each kernel is compiled once per set (`target` attributes on the function that
/// holds the whole hot loop) and chosen at run time. Every set gives bit-identical results.
enum class Isa {
  Portable,  ///< the build's baseline (SSE2 on x86-64)
  Avx2,      ///< AVX2 (4 doubles a vector)
  Avx512     ///< AVX-512 F/DQ/VL (8 doubles a vector)
};

/// The set the kernels use: the best the CPU has, lowered (never raised) by the environment
/// variable GMOTION_ISA=portable|avx2|avx512, read once. CI runs the goldens with
/// GMOTION_ISA=portable too, so every path is checked on a machine that has them all.
Isa active_isa();

/// "portable", "avx2" or "avx512".
const char* isa_name(Isa isa);

}  // namespace gm
