/* libFuzzer target: the PLY reader and writer (body in fuzz_reader.h). */
#define SK_FUZZ_FORMAT SK_FORMAT_PLY
#define SK_FUZZ_NAME "fuzz.ply"
#include "fuzz_reader.h"
