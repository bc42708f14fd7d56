// libFuzzer target: ml::fuzz::parse_text (entry_points.h).
#include "entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return ml::fuzz::run(data, size, ml::fuzz::parse_text);
}
