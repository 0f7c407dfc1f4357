/* The result log on a POSIX file system (see pitvol/result_log.h):
 * pwrite + fsync per record, directory fsync when segments come and go. */
#define _GNU_SOURCE
#include "pitvol/result_log.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "pitvol/crc32c.h"
#include "pitvol/le_bytes.h"

_Static_assert(PV_LOG_END > PV_STATUS_BASE_LOG &&
                   PV_LOG_ERR_CORRUPT < PV_STATUS_BASE_LOG + PV_STATUS_RANGE,
               "pv_log_status_t in its range (pitvol/status_codes.h)");

#define SEG_NAME_FMT "seg-%08u.pvlog"
#define SEG_NAME_LEN 18 /* "seg-" + 8 digits + ".pvlog" */
#define MAX_LISTED 1024u
/* The record-number floor (docs/protocol/result-log.md): magic "PVF1",
 * the number, CRC-32C of the 8 bytes before; written only when recovery
 * cuts records that were whole, so that their numbers stay used. */
#define FLOOR_NAME "floor.pvlog"
#define FLOOR_TMP_NAME "floor.pvlog.tmp"
#define FLOOR_MAGIC 0x31465650u
#define PV_LOG_SEQ_LIMIT 0x80000000u

const char *pv_log_status_name(pv_log_status_t status) {
  switch (status) {
    case PV_LOG_OK: return "PV_LOG_OK";
    case PV_LOG_END: return "PV_LOG_END";
    case PV_LOG_ERR_INVALID_ARGUMENT: return "PV_LOG_ERR_INVALID_ARGUMENT";
    case PV_LOG_ERR_TOO_LARGE: return "PV_LOG_ERR_TOO_LARGE";
    case PV_LOG_ERR_IO: return "PV_LOG_ERR_IO";
    case PV_LOG_ERR_CORRUPT: return "PV_LOG_ERR_CORRUPT";
  }
  return "PV_LOG_ERR_UNKNOWN";
}

const char *pv_log_status_message(pv_log_status_t status) {
  switch (status) {
    case PV_LOG_OK: return "stored";
    case PV_LOG_END: return "no more results in the log";
    case PV_LOG_ERR_INVALID_ARGUMENT:
      return "the result log was opened with a bad setting or path; a configuration bug";
    case PV_LOG_ERR_TOO_LARGE:
      return "a result record is larger than the log allows; a bug, please report it";
    case PV_LOG_ERR_IO:
      return "the result log could not be written or read; the result is still on "
             "screen: note it by hand, then check the storage card (full or failing?)";
    case PV_LOG_ERR_CORRUPT:
      return "a stored result no longer matches its checksum; the storage is failing: "
             "fetch the log to a computer and replace the card";
  }
  return "unknown result log status";
}

void pv_log_config_default(pv_log_config_t *cfg) {
  if (!cfg) return;
  cfg->segment_bytes = 64u * 1024u;
  cfg->max_segments = 16u;
}

static pv_log_status_t io_error(pv_log_t *log) {
  log->last_errno = errno;
  return PV_LOG_ERR_IO;
}

static int open_segment(const pv_log_t *log, uint32_t number, int flags) {
  char name[SEG_NAME_LEN + 8];
  snprintf(name, sizeof name, SEG_NAME_FMT, number);
  return openat(log->dir_fd, name, flags | O_CLOEXEC, 0644);
}

/* Full pread; 1 if all n bytes came. */
static int read_at(int fd, void *buf, size_t n, off_t at) {
  uint8_t *p = (uint8_t *)buf;
  while (n > 0) {
    const ssize_t r = pread(fd, p, n, at);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return 0;
    p += r;
    n -= (size_t)r;
    at += r;
  }
  return 1;
}

static int write_at(int fd, const void *buf, size_t n, off_t at) {
  const uint8_t *p = (const uint8_t *)buf;
  while (n > 0) {
    const ssize_t r = pwrite(fd, p, n, at);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return 0;
    p += r;
    n -= (size_t)r;
    at += r;
  }
  return 1;
}

/* Reads the record at offset `at` of fd (file size `size`) into rec (cap
 * bytes, header + payload + crc). Returns its length, or 0 if no complete,
 * valid record starts there. */
static size_t read_record(int fd, off_t at, off_t size, uint8_t *rec, size_t cap) {
  if (at + (off_t)PV_LOG_HEADER_BYTES > size) return 0;
  if (!read_at(fd, rec, PV_LOG_HEADER_BYTES, at)) return 0;
  if (pv_get_le32(rec) != PV_LOG_RECORD_MAGIC) return 0;
  const uint32_t len = pv_get_le32(rec + 8);
  if (len > PV_LOG_MAX_PAYLOAD_BYTES) return 0;
  const size_t total = PV_LOG_RECORD_BYTES(len);
  if (total > cap || at + (off_t)total > size) return 0;
  if (!read_at(fd, rec + PV_LOG_HEADER_BYTES, total - PV_LOG_HEADER_BYTES,
               at + (off_t)PV_LOG_HEADER_BYTES))
    return 0;
  const size_t body = total - PV_LOG_CRC_BYTES;
  if (pv_crc32c(0, rec, body) != pv_get_le32(rec + body)) return 0;
  return total;
}

static int cmp_u32(const void *a, const void *b) {
  const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
  return (x > y) - (x < y);
}

/* Segment numbers in the directory, ascending. */
static pv_log_status_t list_segments(pv_log_t *log, uint32_t *nums, uint32_t *count) {
  *count = 0;
  const int fd = dup(log->dir_fd);
  if (fd < 0) return io_error(log);
  DIR *d = fdopendir(fd);
  if (!d) {
    close(fd);
    return io_error(log);
  }
  rewinddir(d);
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    unsigned n = 0;
    int end = 0;
    if (strlen(e->d_name) != SEG_NAME_LEN) continue;
    if (sscanf(e->d_name, "seg-%8u.pvlog%n", &n, &end) != 1 || end != SEG_NAME_LEN) continue;
    if (n == 0 || *count == MAX_LISTED) continue;
    nums[(*count)++] = n;
  }
  closedir(d);
  qsort(nums, *count, sizeof *nums, cmp_u32);
  return PV_LOG_OK;
}

static void drop_oldest(pv_log_t *log) {
  char name[SEG_NAME_LEN + 8];
  snprintf(name, sizeof name, SEG_NAME_FMT, log->segs[0]);
  (void)unlinkat(log->dir_fd, name, 0);
  if (log->read_fd >= 0 && log->read_seg == log->segs[0]) {
    close(log->read_fd);
    log->read_fd = -1;
  }
  memmove(log->segs, log->segs + 1, (log->seg_count - 1) * sizeof log->segs[0]);
  log->seg_count--;
}

/* Seq of the first record of segment `number`, 0 if it has none. */
static uint32_t segment_first_seq(const pv_log_t *log, uint32_t number) {
  const int fd = open_segment(log, number, O_RDONLY);
  if (fd < 0) return 0;
  uint8_t head[PV_LOG_HEADER_BYTES];
  uint32_t seq = 0;
  if (read_at(fd, head, sizeof head, 0) && pv_get_le32(head) == PV_LOG_RECORD_MAGIC)
    seq = pv_get_le32(head + 4);
  close(fd);
  return seq;
}

static void update_first_seq(pv_log_t *log) {
  log->first_seq = 0;
  for (uint32_t i = 0; i < log->seg_count && log->first_seq == 0; ++i)
    log->first_seq = segment_first_seq(log, log->segs[i]);
}

/* The stored floor, 0 if there is none or it is damaged. */
static uint32_t read_floor(const pv_log_t *log) {
  const int fd = openat(log->dir_fd, FLOOR_NAME, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  uint8_t b[12];
  const int ok = read_at(fd, b, sizeof b, 0);
  close(fd);
  if (!ok || pv_get_le32(b) != FLOOR_MAGIC || pv_crc32c(0, b, 8) != pv_get_le32(b + 8)) return 0;
  return pv_get_le32(b + 4);
}

/* Stores the floor durably: a temporary file, fsync, rename over the old
 * one, fsync of the directory (a cut leaves the old floor or the new). */
static pv_log_status_t write_floor(pv_log_t *log, uint32_t floor) {
  uint8_t b[12];
  pv_put_le32(b, FLOOR_MAGIC);
  pv_put_le32(b + 4, floor);
  pv_put_le32(b + 8, pv_crc32c(0, b, 8));
  const int fd = openat(log->dir_fd, FLOOR_TMP_NAME, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return io_error(log);
  const int ok = write_at(fd, b, sizeof b, 0) && fsync(fd) == 0;
  close(fd);
  if (!ok || renameat(log->dir_fd, FLOOR_TMP_NAME, log->dir_fd, FLOOR_NAME) != 0 ||
      fsync(log->dir_fd) != 0)
    return io_error(log);
  return PV_LOG_OK;
}

/* Complete records after the first damaged one (from `at` to `size`): a
 * power cut tears only the record being written, so a valid record behind
 * the damage was written and acknowledged before the storage failed. The
 * cut loses it; its number is raised into seq_floor so that no later
 * record takes it (the host may hold it). Found by their magic at any byte
 * offset and checked whole (length, CRC) by read_record. */
static void note_lost_records(pv_log_t *log, int fd, off_t at, off_t size, uint8_t *rec,
                              size_t cap) {
  uint8_t win[4096];
  const uint8_t magic[4] = {(uint8_t)PV_LOG_RECORD_MAGIC, (uint8_t)(PV_LOG_RECORD_MAGIC >> 8),
                            (uint8_t)(PV_LOG_RECORD_MAGIC >> 16),
                            (uint8_t)(PV_LOG_RECORD_MAGIC >> 24)};
  for (off_t base = at + 1; base + (off_t)PV_LOG_HEADER_BYTES <= size;) {
    const off_t left = size - base;
    const size_t n = left < (off_t)sizeof win ? (size_t)left : sizeof win;
    if (!read_at(fd, win, n, base)) return;
    size_t i = 0;
    for (; i + sizeof magic <= n; ++i) {
      if (memcmp(win + i, magic, sizeof magic) != 0) continue;
      const off_t off = base + (off_t)i;
      const size_t len = read_record(fd, off, size, rec, cap);
      if (len == 0) continue;
      /* Numbers from 2^31 on are never reached by a log (some 4000 results
       * a MiB): such a record is forged or garbage that happens to check,
       * and is ignored rather than allowed to wrap the numbering. The
       * damaged record's own number is unknown (an earlier segment may be
       * gone, or rotated away), so no tighter bound is sound. */
      const uint32_t seq = pv_get_le32(rec + 4);
      if (seq > log->last_seq && seq < PV_LOG_SEQ_LIMIT) {
        log->recovery.records_lost++;
        if (seq > log->seq_floor) log->seq_floor = seq;
      }
    }
    /* The last 3 bytes may start a magic that crosses the window. */
    base += (off_t)(n > sizeof magic ? n - (sizeof magic - 1) : n);
  }
}

/* Keeps the complete records of one segment, cuts a torn tail. */
static pv_log_status_t recover_segment(pv_log_t *log, uint32_t number, int *fd_out,
                                       uint32_t *size_out) {
  const int fd = open_segment(log, number, O_RDWR);
  if (fd < 0) return io_error(log);
  struct stat st;
  if (fstat(fd, &st) != 0) {
    close(fd);
    return io_error(log);
  }
  uint8_t rec[PV_LOG_RECORD_BYTES(PV_LOG_MAX_PAYLOAD_BYTES)];
  off_t at = 0;
  for (;;) {
    const size_t n = read_record(fd, at, st.st_size, rec, sizeof rec);
    if (n == 0) break;
    const uint32_t seq = pv_get_le32(rec + 4);
    if (seq == 0 || seq <= log->last_seq) break; /* stale or foreign: not ours */
    if (log->first_seq == 0) log->first_seq = seq;
    log->last_seq = seq;
    if (seq > log->seq_floor) log->seq_floor = seq;
    log->recovery.records++;
    at += (off_t)n;
  }
  if (at < st.st_size) {
    log->recovery.torn_bytes += (uint32_t)(st.st_size - at);
    log->recovery.segments_torn++;
    note_lost_records(log, fd, at, st.st_size, rec, sizeof rec);
    if (ftruncate(fd, at) != 0 || fsync(fd) != 0) {
      close(fd);
      return io_error(log);
    }
  }
  *fd_out = fd;
  *size_out = (uint32_t)at;
  return PV_LOG_OK;
}

static pv_log_status_t new_segment(pv_log_t *log) {
  const uint32_t number = log->seg_count ? log->segs[log->seg_count - 1] + 1 : 1;
  const int fd = open_segment(log, number, O_RDWR | O_CREAT | O_TRUNC);
  if (fd < 0) return io_error(log);
  if (fsync(log->dir_fd) != 0) {
    close(fd);
    return io_error(log);
  }
  if (log->fd >= 0) close(log->fd);
  log->fd = fd;
  log->active_bytes = 0;
  log->segs[log->seg_count++] = number;
  int dropped = 0;
  while (log->seg_count > log->cfg.max_segments) {
    drop_oldest(log);
    dropped = 1;
  }
  if (dropped) {
    if (fsync(log->dir_fd) != 0) return io_error(log);
    update_first_seq(log);
  }
  return PV_LOG_OK;
}

pv_log_status_t pv_log_open(pv_log_t *log, const char *dir, const pv_log_config_t *cfg) {
  if (!log || !dir || !cfg) return PV_LOG_ERR_INVALID_ARGUMENT;
  memset(log, 0, sizeof *log);
  log->fd = log->dir_fd = log->read_fd = -1;
  if (strlen(dir) >= sizeof log->dir) return PV_LOG_ERR_INVALID_ARGUMENT;
  if (cfg->segment_bytes < PV_LOG_RECORD_BYTES(PV_LOG_MAX_PAYLOAD_BYTES) ||
      cfg->segment_bytes > (1u << 30) || cfg->max_segments < 2 ||
      cfg->max_segments > PV_LOG_MAX_SEGMENTS)
    return PV_LOG_ERR_INVALID_ARGUMENT;
  strcpy(log->dir, dir);
  log->cfg = *cfg;
  if (mkdir(dir, 0755) != 0 && errno != EEXIST) return io_error(log);
  log->dir_fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (log->dir_fd < 0) return io_error(log);

  uint32_t nums[MAX_LISTED], count = 0;
  pv_log_status_t st = list_segments(log, nums, &count);
  if (st != PV_LOG_OK) return st;
  log->recovery.segments = count;
  /* More segments than allowed (a smaller max_segments): the oldest go. */
  const uint32_t skip = count > cfg->max_segments ? count - cfg->max_segments : 0;
  for (uint32_t i = 0; i < skip; ++i) {
    log->segs[0] = nums[i];
    log->seg_count = 1;
    drop_oldest(log);
  }
  for (uint32_t i = skip; i < count; ++i) {
    int fd = -1;
    uint32_t size = 0;
    st = recover_segment(log, nums[i], &fd, &size);
    if (st != PV_LOG_OK) return st;
    if (log->fd >= 0) close(log->fd);
    log->fd = fd;
    log->active_bytes = size;
    log->segs[log->seg_count++] = nums[i];
  }
  if (skip && fsync(log->dir_fd) != 0) return io_error(log);
  /* Numbers of records cut by an earlier recovery stay used (the cut bytes
   * are gone from the segments); a recovery that cut whole records now
   * stores its new floor before any append can take those numbers. */
  const uint32_t stored = read_floor(log);
  if (log->seq_floor > log->last_seq && log->seq_floor > stored) {
    st = write_floor(log, log->seq_floor);
    if (st != PV_LOG_OK) return st;
  }
  if (stored > log->seq_floor) log->seq_floor = stored;
  if (log->seg_count == 0) return new_segment(log);
  return PV_LOG_OK;
}

void pv_log_close(pv_log_t *log) {
  if (!log) return;
  if (log->fd >= 0) close(log->fd);
  if (log->read_fd >= 0) close(log->read_fd);
  if (log->dir_fd >= 0) close(log->dir_fd);
  log->fd = log->read_fd = log->dir_fd = -1;
}

pv_log_status_t pv_log_append(pv_log_t *log, const void *payload, size_t len,
                              uint32_t *seq_out) {
  if (!log || (!payload && len) || log->fd < 0) return PV_LOG_ERR_INVALID_ARGUMENT;
  if (len > PV_LOG_MAX_PAYLOAD_BYTES) return PV_LOG_ERR_TOO_LARGE;
  const size_t total = PV_LOG_RECORD_BYTES(len);
  if (log->active_bytes > 0 && log->active_bytes + total > log->cfg.segment_bytes) {
    const pv_log_status_t st = new_segment(log);
    if (st != PV_LOG_OK) return st;
  }
  uint8_t rec[PV_LOG_RECORD_BYTES(PV_LOG_MAX_PAYLOAD_BYTES)];
  const uint32_t seq = log->seq_floor + 1;
  pv_put_le32(rec, PV_LOG_RECORD_MAGIC);
  pv_put_le32(rec + 4, seq);
  pv_put_le32(rec + 8, (uint32_t)len);
  if (len) memcpy(rec + PV_LOG_HEADER_BYTES, payload, len);
  pv_put_le32(rec + total - PV_LOG_CRC_BYTES, pv_crc32c(0, rec, total - PV_LOG_CRC_BYTES));
  if (!write_at(log->fd, rec, total, (off_t)log->active_bytes) || fsync(log->fd) != 0) {
    const pv_log_status_t st = io_error(log);
    /* Leave no half record behind for the next append to follow. */
    if (ftruncate(log->fd, (off_t)log->active_bytes) == 0) (void)fsync(log->fd);
    return st;
  }
  log->active_bytes += (uint32_t)total;
  log->last_seq = log->seq_floor = seq;
  if (log->first_seq == 0) log->first_seq = seq;
  if (seq_out) *seq_out = seq;
  return PV_LOG_OK;
}

uint32_t pv_log_first_seq(const pv_log_t *log) { return log ? log->first_seq : 0; }
uint32_t pv_log_last_seq(const pv_log_t *log) { return log ? log->last_seq : 0; }

pv_log_status_t pv_log_seek(const pv_log_t *log, uint32_t from_seq, pv_log_cursor_t *cur) {
  if (!log || !cur || log->seg_count == 0) return PV_LOG_ERR_INVALID_ARGUMENT;
  cur->next_seq = from_seq ? from_seq : 1;
  cur->segment = log->segs[0];
  cur->offset = 0;
  /* Start in the newest segment whose first record is not past from_seq. */
  for (uint32_t i = log->seg_count; i-- > 1;) {
    const uint32_t first = segment_first_seq(log, log->segs[i]);
    if (first != 0 && first <= cur->next_seq) {
      cur->segment = log->segs[i];
      break;
    }
  }
  return PV_LOG_OK;
}

pv_log_status_t pv_log_next(pv_log_t *log, pv_log_cursor_t *cur, void *buf, size_t cap,
                            uint32_t *seq_out, size_t *len_out) {
  if (!log || !cur || (!buf && cap) || !seq_out || !len_out) return PV_LOG_ERR_INVALID_ARGUMENT;
  for (;;) {
    if (log->seg_count == 0 || cur->next_seq > log->last_seq) return PV_LOG_END;
    if (cur->segment < log->segs[0]) { /* rotated away meanwhile */
      cur->segment = log->segs[0];
      cur->offset = 0;
    }
    uint32_t i = 0;
    while (i < log->seg_count && log->segs[i] < cur->segment) ++i;
    if (i == log->seg_count) return PV_LOG_END;
    cur->segment = log->segs[i];
    const int active = i == log->seg_count - 1;
    if (log->read_fd < 0 || log->read_seg != cur->segment) {
      if (log->read_fd >= 0) close(log->read_fd);
      log->read_fd = open_segment(log, cur->segment, O_RDONLY);
      if (log->read_fd < 0) return io_error(log);
      log->read_seg = cur->segment;
    }
    off_t size = log->active_bytes;
    if (!active) {
      struct stat st;
      if (fstat(log->read_fd, &st) != 0) return io_error(log);
      size = st.st_size;
    }
    if ((off_t)cur->offset >= size) {
      if (active) return PV_LOG_END;
      cur->segment++; /* on to the next segment */
      cur->offset = 0;
      continue;
    }
    uint8_t head[PV_LOG_HEADER_BYTES];
    if (!read_at(log->read_fd, head, sizeof head, cur->offset)) return PV_LOG_ERR_CORRUPT;
    const uint32_t seq = pv_get_le32(head + 4), len = pv_get_le32(head + 8);
    if (pv_get_le32(head) != PV_LOG_RECORD_MAGIC || len > PV_LOG_MAX_PAYLOAD_BYTES)
      return PV_LOG_ERR_CORRUPT;
    const uint32_t total = (uint32_t)PV_LOG_RECORD_BYTES(len);
    if (seq < cur->next_seq) { /* before the start: skip without reading */
      cur->offset += total;
      continue;
    }
    if (len > cap) return PV_LOG_ERR_TOO_LARGE;
    uint8_t crc[PV_LOG_CRC_BYTES];
    if (!read_at(log->read_fd, buf, len, (off_t)cur->offset + PV_LOG_HEADER_BYTES) ||
        !read_at(log->read_fd, crc, sizeof crc, (off_t)cur->offset + PV_LOG_HEADER_BYTES + len))
      return PV_LOG_ERR_CORRUPT;
    if (pv_crc32c(pv_crc32c(0, head, sizeof head), buf, len) != pv_get_le32(crc))
      return PV_LOG_ERR_CORRUPT;
    cur->offset += total;
    cur->next_seq = seq + 1;
    *seq_out = seq;
    *len_out = len;
    return PV_LOG_OK;
  }
}
