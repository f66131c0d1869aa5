// The libFuzzer entry point each fuzz target defines; replay_main.cpp calls it without libFuzzer.
#pragma once

#include <cstddef>
#include <cstdint>

/// Runs one input through the target. Returns 0 (libFuzzer's convention: keep the input).
/// Any failure — a crash, an escaping exception other than the documented gm::InputError,
/// a broken invariant (abort) or undefined behaviour under UBSan — is a bug.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
