// libFuzzer target: ml::fuzz::decode_view_message (entry_points.h).
#include "entry_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return ml::fuzz::run(data, size, ml::fuzz::decode_view_message);
}
