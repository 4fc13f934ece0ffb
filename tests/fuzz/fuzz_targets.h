// Fuzz targets for the two parsers that read files people edit by hand or
// export from other tools: scenarios and glTF. The same functions run under
// libFuzzer (fuzz_*_main.cpp, clang with ASan + UBSan, `.ci/fuzz`) and, over
// the committed corpus, inside the test suite (tests/fuzz_corpus_test.cpp).
//
// Contract: bad input ends in gi::InputError (caught here); any other
// exception, crash or sanitizer report is a bug.
#pragma once
#include <cstddef>
#include <cstdint>

namespace gi::fuzz {

// Bytes as a scenario file: parse, and for generator scenes also build the
// scene and validate the events (glTF scene files are not opened).
void scenario_input(const std::uint8_t* data, std::size_t size);

// Bytes as a glTF file (.glb when they start with the "glTF" magic, else
// .gltf JSON), imported from a private temporary folder.
void gltf_input(const std::uint8_t* data, std::size_t size);

}  // namespace gi::fuzz
