#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#ifdef TIGRIS_SANITIZE
// The sanitizer build runs as it is: LeakSanitizer's tracer crashes on SystemC's coroutine
// stacks ("Tracer caught signal 11"), so leak checking is off there (ASan and UBSan stay on).
extern "C" const char* __asan_default_options() { return "detect_leaks=0"; }
#endif
