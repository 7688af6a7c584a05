/* libFuzzer target: the OBJ reader and writer (body in fuzz_reader.h). */
#define SK_FUZZ_FORMAT SK_FORMAT_OBJ
#define SK_FUZZ_NAME "fuzz.obj"
#include "fuzz_reader.h"
