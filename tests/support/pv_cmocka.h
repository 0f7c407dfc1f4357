// cmocka 1.1.5's header has no extern "C" guard and needs these first.
// Include this header LAST: cmocka defines macros such as fail() that
// break later standard headers (std::basic_ios::fail).
#ifndef PV_TESTS_CMOCKA_H
#define PV_TESTS_CMOCKA_H
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <csetjmp>
extern "C" {
#include <cmocka.h>
}
#endif
