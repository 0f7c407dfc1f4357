/*
 * CRC-32C (Castagnoli): the checksum of every pitvol wire and storage
 * format (USB frames, serial link frames, result log records). One copy so
 * the three cannot drift.
 */
#ifndef PITVOL_CRC32C_H
#define PITVOL_CRC32C_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* CRC-32C (Castagnoli, reflected, init and xorout 0xFFFFFFFF).
 * crc32c("123456789") == 0xE3069283. Chain: pass the previous result. */
uint32_t pv_crc32c(uint32_t crc, const void *data, size_t len);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_CRC32C_H */
