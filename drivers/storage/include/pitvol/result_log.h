/*
 * The board's result log: append-only, power-loss safe, bounded.
 * docs/protocol/result-log.md describes the format; keep the two in step.
 *
 * A log is a directory of segment files "seg-NNNNNNNN.pvlog" (NNNNNNNN: the
 * segment number, decimal, rising). Each segment is a run of records, all
 * little endian:
 *
 *   offset  size  field
 *   0       4     magic     0x31525650 ("PVR1" as bytes)
 *   4       4     seq       record number: 1, 2, 3 ... rising by 1, never reused
 *   8       4     length    payload bytes, 0 .. PV_LOG_MAX_PAYLOAD_BYTES
 *   12      n     payload   (the board: a nanopb-encoded pitvol.Result)
 *   12+n    4     crc32c    CRC-32C of bytes 0 .. 12+n-1
 *
 * Append writes one record with one write() and fsync()s it before it
 * returns: a record is durable when pv_log_append says PV_LOG_OK. A power
 * cut can only leave a torn tail in the newest segment; pv_log_open() keeps
 * every complete record and cuts the file after the last one (it never
 * invents a record: a record counts only with its magic, a length in range,
 * a matching CRC and a seq above the one before). When the active segment
 * would pass segment_bytes the next record starts a new segment, and the
 * oldest segment is deleted once there are more than max_segments: the log
 * never grows past about segment_bytes * max_segments.
 *
 * No allocation: the log state and cursors are plain structs.
 */
#ifndef PITVOL_RESULT_LOG_H
#define PITVOL_RESULT_LOG_H

#include <stddef.h>
#include <stdint.h>

#include "pitvol/status_codes.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PV_LOG_RECORD_MAGIC 0x31525650u
#define PV_LOG_HEADER_BYTES 12u
#define PV_LOG_CRC_BYTES 4u
#define PV_LOG_MAX_PAYLOAD_BYTES 1024u
#define PV_LOG_RECORD_BYTES(n) (PV_LOG_HEADER_BYTES + (size_t)(n) + PV_LOG_CRC_BYTES)
#define PV_LOG_MAX_SEGMENTS 64u
#define PV_LOG_PATH_MAX 512u

typedef enum pv_log_status {
  /* 0, then 400 .. 499: PV_STATUS_BASE_LOG (pitvol/status_codes.h) */
  PV_LOG_OK = 0,
  PV_LOG_END = 401,                  /* cursor: no more records */
  PV_LOG_ERR_INVALID_ARGUMENT = 402, /* NULL, a config out of range, a path too long */
  PV_LOG_ERR_TOO_LARGE = 403,        /* payload > PV_LOG_MAX_PAYLOAD_BYTES or > a segment */
  PV_LOG_ERR_IO = 404,               /* the file system refused (errno kept in the log) */
  PV_LOG_ERR_CORRUPT = 405           /* a record read back does not match its CRC */
} pv_log_status_t;

const char *pv_log_status_name(pv_log_status_t status);
/* A sentence for the user: what went wrong and what to do. Never NULL. */
const char *pv_log_status_message(pv_log_status_t status);

typedef struct pv_log_config {
  uint32_t segment_bytes; /* >= PV_LOG_RECORD_BYTES(PV_LOG_MAX_PAYLOAD_BYTES) */
  uint32_t max_segments;  /* 2 .. PV_LOG_MAX_SEGMENTS */
} pv_log_config_t;

/* 64 KiB segments, 16 of them: about 1 MiB, some 4000 results. */
void pv_log_config_default(pv_log_config_t *cfg);

/* What pv_log_open() found and repaired. */
typedef struct pv_log_recovery {
  uint32_t segments;       /* segment files found */
  uint32_t records;        /* complete records kept */
  uint32_t torn_bytes;     /* bytes cut off after the last complete record(s) */
  uint32_t segments_torn;  /* segments that had a torn tail */
  uint32_t records_lost;   /* complete records found after a damaged one and
                              cut with it (storage damage, not a power cut:
                              a cut only tears the last record) */
} pv_log_recovery_t;

typedef struct pv_log {
  char dir[PV_LOG_PATH_MAX];
  int dir_fd;
  int fd;                              /* active (newest) segment, -1 if none */
  pv_log_config_t cfg;
  uint32_t segs[PV_LOG_MAX_SEGMENTS + 1]; /* segment numbers, oldest first */
  uint32_t seg_count;
  uint32_t active_bytes;               /* size of the active segment */
  uint32_t first_seq, last_seq;        /* 0, 0 when empty */
  uint32_t seq_floor;                  /* the highest record number ever seen,
                                          kept or lost: appends go above it,
                                          so a number is never reused */
  int read_fd;                         /* segment a cursor reads, -1 if none */
  uint32_t read_seg;
  int last_errno;                      /* of the last PV_LOG_ERR_IO */
  pv_log_recovery_t recovery;
} pv_log_t;

/* Opens (creating if needed) the log in directory dir and recovers it. */
PV_NODISCARD pv_log_status_t pv_log_open(pv_log_t *log, const char *dir,
                                         const pv_log_config_t *cfg);
void pv_log_close(pv_log_t *log);

/* Appends one record and makes it durable (fsync). seq_out may be NULL. */
PV_NODISCARD pv_log_status_t pv_log_append(pv_log_t *log, const void *payload, size_t len,
                                           uint32_t *seq_out);

/* Oldest and newest record numbers (0, 0 when empty). */
uint32_t pv_log_first_seq(const pv_log_t *log);
uint32_t pv_log_last_seq(const pv_log_t *log);

/* Reading, oldest first, from a record number on:
 *   pv_log_cursor_t c;  pv_log_seek(log, from_seq, &c);
 *   while (pv_log_next(log, &c, buf, sizeof buf, &seq, &len) == PV_LOG_OK) ...
 * A cursor survives appends and rotation (records deleted meanwhile are
 * skipped). */
typedef struct pv_log_cursor {
  uint32_t next_seq;   /* the smallest record number still wanted */
  uint32_t segment;    /* segment number being read */
  uint32_t offset;     /* byte offset of the next record in it */
} pv_log_cursor_t;

PV_NODISCARD pv_log_status_t pv_log_seek(const pv_log_t *log, uint32_t from_seq,
                                         pv_log_cursor_t *cur);
/* PV_LOG_OK (one record in buf), PV_LOG_END, PV_LOG_ERR_CORRUPT, _IO or
 * _TOO_LARGE (cap smaller than the record). */
PV_NODISCARD pv_log_status_t pv_log_next(pv_log_t *log, pv_log_cursor_t *cur, void *buf, size_t cap,
                                         uint32_t *seq_out, size_t *len_out);

#ifdef __cplusplus
}
#endif
#endif /* PITVOL_RESULT_LOG_H */
