/* libFuzzer target: the OFF reader and writer (body in fuzz_reader.h). */
#define SK_FUZZ_FORMAT SK_FORMAT_OFF
#define SK_FUZZ_NAME "fuzz.off"
#include "fuzz_reader.h"
