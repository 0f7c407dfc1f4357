/*
 * COBS (Consistent Overhead Byte Stuffing, Cheshire & Baker 1999): turns any
 * byte string into one without zero bytes, so a zero can delimit frames on
 * the serial line and a reader resynchronises at the next zero after noise.
 * Written here (about 40 lines) because Debian packages no C COBS library.
 */
#ifndef PITVOL_COBS_H
#define PITVOL_COBS_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Worst-case encoded size of n bytes (no delimiter): one code byte per
 * 254 data bytes, plus one. */
#define PV_COBS_MAX_ENCODED(n) ((n) + (n) / 254u + 1u)

/* Encodes len bytes into out (cap bytes). Returns the encoded length (no
 * zero inside, no delimiter added), or 0 if cap is too small. */
PV_NODISCARD size_t pv_cobs_encode(const uint8_t *in, size_t len, uint8_t *out, size_t cap);

/* Decodes len encoded bytes (no delimiter) into out (cap bytes). Returns the
 * decoded length; sets *ok to 0 (and returns 0) if the input holds a zero,
 * a code byte points past the end, or out is too small. */
PV_NODISCARD size_t pv_cobs_decode(const uint8_t *in, size_t len, uint8_t *out, size_t cap,
                                   int *ok);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_COBS_H */
