/*
 * What every C module's status follows. Header only and free of
 * dependencies: the core and every module above it include it.
 */
#ifndef PITVOL_STATUS_CODES_H
#define PITVOL_STATUS_CODES_H

/* For functions that can fail: a caller that drops the status does not
 * compile (pv_strict's -Werror=unused-result). C++ may drop one on purpose
 * with a (void) cast; GCC's C attribute ignores that cast, so C code keeps
 * the status in a variable and says why it is not acted on. */
#if defined(__cplusplus) && __cplusplus >= 201703L
#define PV_NODISCARD [[nodiscard]]
#elif defined(__GNUC__) || defined(__clang__)
#define PV_NODISCARD __attribute__((warn_unused_result))
#else
#define PV_NODISCARD
#endif

#endif /* PITVOL_STATUS_CODES_H */
