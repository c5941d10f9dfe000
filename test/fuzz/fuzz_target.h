// The interface every fuzz target of test/fuzz/ implements: libFuzzer's entry point. Built
// with clang's -fsanitize=fuzzer by scripts/fuzz, or with the in-tree driver
// (fuzz_driver.cpp) as a unit test under gcc. A target feeds the bytes to one loader and
// accepts only a result or a std::exception (the loader's clear error); a crash, a
// sanitizer report or a hang is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace soccer_vision_fuzz {

inline std::string asText(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace soccer_vision_fuzz
