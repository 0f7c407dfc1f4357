/* COBS encoder and decoder (see pitvol/cobs.h). */
#include "pitvol/cobs.h"

size_t pv_cobs_encode(const uint8_t *in, size_t len, uint8_t *out, size_t cap) {
  if (cap < PV_COBS_MAX_ENCODED(len)) return 0;
  size_t code_at = 0, o = 1;
  uint8_t code = 1;
  for (size_t i = 0; i < len; ++i) {
    if (in[i] == 0) {
      out[code_at] = code;
      code_at = o++;
      code = 1;
    } else {
      out[o++] = in[i];
      /* A full block of 254 non-zero bytes ends without a zero; the next
       * block starts only if data follows (the canonical encoding). */
      if (++code == 0xff && i + 1 < len) {
        out[code_at] = code;
        code_at = o++;
        code = 1;
      }
    }
  }
  out[code_at] = code;
  return o;
}

size_t pv_cobs_decode(const uint8_t *in, size_t len, uint8_t *out, size_t cap, int *ok) {
  size_t i = 0, o = 0;
  *ok = 0;
  if (len == 0) return 0;
  while (i < len) {
    const uint8_t code = in[i++];
    if (code == 0 || i + (size_t)(code - 1) > len) return 0;
    for (uint8_t k = 1; k < code; ++k) {
      if (in[i] == 0 || o >= cap) return 0;
      out[o++] = in[i++];
    }
    /* A block shorter than 254 stands for a zero, except at the very end. */
    if (code != 0xff && i < len) {
      if (o >= cap) return 0;
      out[o++] = 0;
    }
  }
  *ok = 1;
  return o;
}
