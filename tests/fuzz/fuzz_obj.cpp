// libFuzzer target for the OBJ reader (fuzz_reader.hpp).
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return wish::fuzz::fuzz_reader(wish::MeshFormat::Obj, data, size);
}
