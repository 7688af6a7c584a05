/* libFuzzer target: the STL reader and writer (body in fuzz_reader.h). */
#define SK_FUZZ_FORMAT SK_FORMAT_STL
#define SK_FUZZ_NAME "fuzz.stl"
#include "fuzz_reader.h"
