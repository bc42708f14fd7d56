// libFuzzer target: ml::fuzz::read_ply (entry_points.h).
#include "entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return ml::fuzz::run(data, size, ml::fuzz::read_ply);
}
