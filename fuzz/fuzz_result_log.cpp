// The result log's recovery (drivers/storage/result_log_posix.c,
// docs/protocol/result-log.md) on logs damaged in arbitrary ways.
//
// From the input: a configuration (segment size, segment count), up to 48
// records of drawn lengths and bytes appended (rotation included), then a
// damage point D (a byte offset in the segments taken in order) and 1..4
// damage operations at or after D: truncation of a segment (and maybe of
// every later one), bytes overwritten, a bit flipped, garbage appended,
// a segment deleted, an empty segment added (as a power cut while starting
// one leaves it).
//
// Invariants:
//  - the undamaged log reopens with nothing cut and holds the newest records
//    written, in order, byte for byte;
//  - after the damage, open succeeds and never loses a record that ended
//    before D (it comes back byte for byte);
//  - it never yields a record whose checksum fails: reading runs to the end
//    without PV_LOG_ERR_CORRUPT, and the segment files left on disk are,
//    parsed here independently, nothing but records with their magic, a
//    length in range, a matching CRC-32C and rising record numbers, which
//    are exactly the records the cursor yields;
//  - a record read back differs from the one written under its number only
//    if the damage touched that record's bytes;
//  - recovery is stable: a second open cuts nothing and yields the same; an
//    append after it gets a number above the last kept and above every
//    record cut though whole (never a number given before), below 2^31
//    (a forged record cannot bring the numbering to a wrap), and reads back.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "pitvol/crc32c.h"
#include "pitvol/le_bytes.h"
#include "pitvol/result_log.h"

namespace {

using Bytes = std::vector<uint8_t>;

std::string g_dir;

void remove_dir() {
  if (g_dir.empty()) return;
  if (DIR *d = opendir(g_dir.c_str())) {
    while (dirent *e = readdir(d)) {
      if (e->d_name[0] != '.') unlink((g_dir + "/" + e->d_name).c_str());
    }
    closedir(d);
  }
  rmdir(g_dir.c_str());
}

// One directory per process, on tmpfs when there is one (fsync is free).
const std::string &log_dir() {
  if (g_dir.empty()) {
    const char *base = std::getenv("PV_FUZZ_TMPDIR");
    if (!base) base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    std::string tmpl = std::string(base) + "/pv-fuzz-log-XXXXXX";
    if (!mkdtemp(tmpl.data())) std::abort();
    g_dir = tmpl;
    std::atexit(remove_dir);
  }
  return g_dir;
}

// The input read front to back; zeros once it runs out.
struct Input {
  const uint8_t *p;
  size_t n, at = 0;
  uint8_t byte() { return at < n ? p[at++] : 0; }
  uint32_t u16() { return uint32_t(byte()) | uint32_t(byte()) << 8; }
  uint32_t u32() { return u16() | u16() << 16; }
};

struct Segment {
  uint32_t number;
  Bytes bytes;
};

std::string seg_path(uint32_t number) {
  char name[32];
  std::snprintf(name, sizeof name, "/seg-%08u.pvlog", number);
  return log_dir() + name;
}

std::vector<Segment> load_segments() {
  std::vector<Segment> segs;
  DIR *d = opendir(log_dir().c_str());
  PV_FUZZ_CHECK(d != nullptr, "cannot list the log directory");
  while (dirent *e = readdir(d)) {
    unsigned n = 0;
    int end = 0;
    if (std::sscanf(e->d_name, "seg-%8u.pvlog%n", &n, &end) == 1 && end == 18) segs.push_back({n, {}});
  }
  closedir(d);
  std::sort(segs.begin(), segs.end(), [](const Segment &a, const Segment &b) { return a.number < b.number; });
  for (Segment &s : segs) {
    FILE *f = std::fopen(seg_path(s.number).c_str(), "rb");
    PV_FUZZ_CHECK(f != nullptr, "cannot read segment %u", s.number);
    uint8_t buf[4096];
    size_t r;
    while ((r = std::fread(buf, 1, sizeof buf, f)) > 0) s.bytes.insert(s.bytes.end(), buf, buf + r);
    std::fclose(f);
  }
  return segs;
}

void store_segments(const std::vector<Segment> &segs) {
  for (const Segment &s : load_segments()) unlink(seg_path(s.number).c_str());
  unlink((log_dir() + "/floor.pvlog").c_str());  // the record-number floor of a recovery
  for (const Segment &s : segs) {
    FILE *f = std::fopen(seg_path(s.number).c_str(), "wb");
    PV_FUZZ_CHECK(f != nullptr, "cannot write segment %u", s.number);
    if (!s.bytes.empty()) PV_FUZZ_CHECK(std::fwrite(s.bytes.data(), 1, s.bytes.size(), f) == s.bytes.size(), "short write");
    std::fclose(f);
  }
}

struct Record {
  uint32_t seq;
  Bytes payload;
  bool operator==(const Record &o) const { return seq == o.seq && payload == o.payload; }
};

// Where a record sits: its segment number, offset, and its whole bytes.
struct Placed {
  Record rec;
  uint32_t segment;
  size_t offset;
  size_t global_end;  // offset after the record in the segments taken in order
  Bytes raw;
};

// Independent parse of segment files that should hold nothing but valid
// records with rising numbers.
std::vector<Placed> parse_clean(const std::vector<Segment> &segs) {
  std::vector<Placed> out;
  uint32_t last = 0;
  size_t base = 0;
  for (const Segment &s : segs) {
    size_t at = 0;
    while (at < s.bytes.size()) {
      const uint8_t *r = s.bytes.data() + at;
      const size_t left = s.bytes.size() - at;
      PV_FUZZ_CHECK(left >= PV_LOG_HEADER_BYTES + PV_LOG_CRC_BYTES, "segment %u: %zu stray bytes at %zu",
                    s.number, left, at);
      PV_FUZZ_CHECK(pv_get_le32(r) == PV_LOG_RECORD_MAGIC, "segment %u: no magic at %zu", s.number, at);
      const uint32_t seq = pv_get_le32(r + 4), len = pv_get_le32(r + 8);
      PV_FUZZ_CHECK(len <= PV_LOG_MAX_PAYLOAD_BYTES && PV_LOG_RECORD_BYTES(len) <= left,
                    "segment %u: length %u at %zu", s.number, len, at);
      const size_t body = PV_LOG_HEADER_BYTES + len;
      PV_FUZZ_CHECK(pv_crc32c(0, r, body) == pv_get_le32(r + body), "segment %u: CRC fails at %zu",
                    s.number, at);
      PV_FUZZ_CHECK(seq > last, "segment %u: record %u after %u", s.number, seq, last);
      last = seq;
      const size_t total = PV_LOG_RECORD_BYTES(len);
      out.push_back({{seq, Bytes(r + PV_LOG_HEADER_BYTES, r + body)}, s.number, at, base + at + total,
                     Bytes(r, r + total)});
      at += total;
    }
    base += s.bytes.size();
  }
  return out;
}

std::vector<Record> read_all(pv_log_t *log) {
  std::vector<Record> out;
  pv_log_cursor_t cur;
  PV_FUZZ_CHECK(pv_log_seek(log, 1, &cur) == PV_LOG_OK, "seek failed");
  uint8_t buf[PV_LOG_MAX_PAYLOAD_BYTES];
  for (;;) {
    uint32_t seq = 0;
    size_t len = 0;
    const pv_log_status_t st = pv_log_next(log, &cur, buf, sizeof buf, &seq, &len);
    if (st == PV_LOG_END) break;
    PV_FUZZ_CHECK(st == PV_LOG_OK, "reading after recovery: %s (after %zu records)",
                  pv_log_status_name(st), out.size());
    out.push_back({seq, Bytes(buf, buf + len)});
  }
  return out;
}

std::vector<Record> records_of(const std::vector<Placed> &placed) {
  std::vector<Record> out;
  for (const Placed &p : placed) out.push_back(p.rec);
  return out;
}

size_t total_bytes(const std::vector<Segment> &segs) {
  size_t t = 0;
  for (const Segment &s : segs) t += s.bytes.size();
  return t;
}

// The segment holding global offset p (the last one for p == total), and p
// inside it.
size_t locate(const std::vector<Segment> &segs, size_t p, size_t *local) {
  size_t base = 0;
  for (size_t i = 0; i < segs.size(); ++i) {
    if (p < base + segs[i].bytes.size() || i + 1 == segs.size()) {
      *local = std::min(p - std::min(p, base), segs[i].bytes.size());
      return i;
    }
    base += segs[i].bytes.size();
  }
  *local = 0;
  return 0;
}

// Damage at or after global offset d. Returns a short description (for a
// failing case's message).
void damage(std::vector<Segment> &segs, size_t d, uint32_t max_segments, Input &in) {
  const int ops = 1 + in.byte() % 4;
  for (int k = 0; k < ops && !segs.empty(); ++k) {
    const size_t total = total_bytes(segs);
    const size_t p = d + (total > d ? in.u32() % (total - d + 1) : 0);
    size_t local = 0;
    const size_t i = locate(segs, p, &local);
    Segment &s = segs[i];
    const size_t seg_start = p - local;
    switch (in.byte() % 6) {
      case 0:  // a torn write: cut here (and maybe every later segment)
        s.bytes.resize(local);
        if (in.byte() & 1) segs.resize(i + 1);
        break;
      case 1: {  // bytes overwritten
        const size_t n = 1 + in.byte() % 16;
        for (size_t j = 0; j < n && local + j < s.bytes.size(); ++j) s.bytes[local + j] = in.byte();
        break;
      }
      case 2:  // one bit flipped
        if (local < s.bytes.size()) s.bytes[local] ^= uint8_t(1u << (in.byte() % 8));
        break;
      case 3: {  // garbage after the end (a sector written out of order)
        const size_t n = in.byte() % 64;
        for (size_t j = 0; j < n; ++j) segs.back().bytes.push_back(in.byte());
        break;
      }
      case 4:  // a segment lost
        if (seg_start >= d) segs.erase(segs.begin() + long(i));
        break;
      case 5:  // an empty segment (power cut while starting one)
        if (segs.size() < max_segments) segs.push_back({segs.back().number + 1, {}});
        break;
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  Input in{data, size};
  pv_log_config_t cfg;
  cfg.segment_bytes = uint32_t(PV_LOG_RECORD_BYTES(PV_LOG_MAX_PAYLOAD_BYTES) + in.u16() % 3000);
  cfg.max_segments = 2 + in.byte() % 8;
  const std::string &dir = log_dir();
  store_segments({});

  // Write.
  std::map<uint32_t, Bytes> written;
  pv_log_t log;
  PV_FUZZ_CHECK(pv_log_open(&log, dir.c_str(), &cfg) == PV_LOG_OK, "open of an empty log failed");
  const unsigned count = in.byte() % 49;
  for (unsigned r = 0; r < count; ++r) {
    const unsigned l = in.byte();
    const size_t len = l < 128 ? l % 64 : ((l - 128) << 8 | in.byte()) % (PV_LOG_MAX_PAYLOAD_BYTES + 1);
    Bytes payload(len);
    for (size_t j = 0; j < len; ++j) payload[j] = in.at < in.n ? in.byte() : uint8_t(r * 31 + j);
    uint32_t seq = 0;
    PV_FUZZ_CHECK(pv_log_append(&log, payload.data(), len, &seq) == PV_LOG_OK, "append failed");
    PV_FUZZ_CHECK(seq == r + 1, "record %u got number %u", r + 1, seq);
    written[seq] = payload;
  }
  pv_log_close(&log);

  // The undamaged log: nothing cut, the newest records in order.
  PV_FUZZ_CHECK(pv_log_open(&log, dir.c_str(), &cfg) == PV_LOG_OK, "reopen failed");
  PV_FUZZ_CHECK(log.recovery.torn_bytes == 0, "%u bytes cut from an undamaged log", log.recovery.torn_bytes);
  const std::vector<Record> before = read_all(&log);
  pv_log_close(&log);
  const std::vector<Segment> clean = load_segments();
  const std::vector<Placed> placed = parse_clean(clean);
  PV_FUZZ_CHECK(records_of(placed) == before, "the cursor and the files disagree");
  for (size_t i = 0; i < before.size(); ++i) {
    PV_FUZZ_CHECK(before[i].seq == count - before.size() + 1 + i && before[i].payload == written[before[i].seq],
                  "undamaged record %zu of %zu is not the one written", i, before.size());
  }

  // Damage.
  std::vector<Segment> segs = clean;
  const size_t total = total_bytes(segs);
  const size_t d = in.u32() % (total + 1);
  damage(segs, d, cfg.max_segments, in);
  store_segments(segs);

  // Recover.
  const pv_log_status_t st = pv_log_open(&log, dir.c_str(), &cfg);
  PV_FUZZ_CHECK(st == PV_LOG_OK, "open of the damaged log: %s", pv_log_status_name(st));
  const std::vector<Record> after = read_all(&log);
  PV_FUZZ_CHECK(log.recovery.records == after.size(), "recovery kept %u records, reading gives %zu",
                log.recovery.records, after.size());
  pv_log_close(&log);
  const std::vector<Placed> left = parse_clean(load_segments());
  PV_FUZZ_CHECK(records_of(left) == after, "the cursor and the recovered files disagree");

  // Nothing that ended before the damage is lost.
  size_t k = 0;
  for (const Placed &p : placed) {
    if (p.global_end > d) break;
    while (k < after.size() && after[k].seq < p.rec.seq) ++k;
    PV_FUZZ_CHECK(k < after.size() && after[k] == p.rec,
                  "record %u (ending at byte %zu, damage from %zu) lost or changed", p.rec.seq,
                  p.global_end, d);
  }
  // A changed record only where the damage was.
  for (const Record &r : after) {
    const auto w = written.find(r.seq);
    if (w != written.end() && w->second == r.payload) continue;
    const auto orig = std::find_if(placed.begin(), placed.end(), [&](const Placed &p) { return p.rec.seq == r.seq; });
    bool touched = true;
    if (orig != placed.end()) {
      for (const Segment &s : segs) {
        if (s.number == orig->segment && orig->offset + orig->raw.size() <= s.bytes.size() &&
            std::equal(orig->raw.begin(), orig->raw.end(), s.bytes.begin() + long(orig->offset))) {
          touched = false;
        }
      }
    }
    PV_FUZZ_CHECK(touched, "record %u reads back different though its bytes are intact", r.seq);
  }

  // Numbers whose records are still whole in the damaged files but were cut
  // behind a damaged one: written, maybe sent; never to be given again.
  uint32_t lost_max = 0;
  for (const Placed &p : placed) {
    const bool kept = std::any_of(after.begin(), after.end(), [&](const Record &r) { return r.seq == p.rec.seq; });
    if (kept) continue;
    for (const Segment &s : segs) {
      if (s.number == p.segment && p.offset + p.raw.size() <= s.bytes.size() &&
          std::equal(p.raw.begin(), p.raw.end(), s.bytes.begin() + long(p.offset))) {
        lost_max = std::max(lost_max, p.rec.seq);
      }
    }
  }

  // Stable: a second open cuts nothing; an append gets a number above the
  // last kept and above every whole record cut (after a reboot too: the
  // second open), and stays below 2^31.
  PV_FUZZ_CHECK(pv_log_open(&log, dir.c_str(), &cfg) == PV_LOG_OK, "second open failed");
  PV_FUZZ_CHECK(log.recovery.torn_bytes == 0, "second open cut %u bytes", log.recovery.torn_bytes);
  PV_FUZZ_CHECK(read_all(&log) == after, "second open reads differently");
  const uint32_t last = after.empty() ? pv_log_last_seq(&log) : after.back().seq;
  const uint8_t extra[3] = {1, 2, 3};
  uint32_t seq = 0;
  PV_FUZZ_CHECK(pv_log_append(&log, extra, sizeof extra, &seq) == PV_LOG_OK, "append after recovery failed");
  PV_FUZZ_CHECK(seq > last && seq > lost_max, "appended as %u after %u (cut whole: up to %u)", seq, last,
                lost_max);
  // A record forged in the damaged bytes may move the numbering ahead (a
  // gap, never a reuse), but never to the half of the space that wraps.
  PV_FUZZ_CHECK(seq <= 0x80000000u, "appended as %u: numbering about to wrap", seq);
  const std::vector<Record> again = read_all(&log);
  PV_FUZZ_CHECK(!again.empty() && again.back() == (Record{seq, Bytes(extra, extra + 3)}),
                "the appended record does not read back");
  pv_log_close(&log);
  return 0;
}
