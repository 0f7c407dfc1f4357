// Result log: records read back as written, bounded size with rotation,
// and the power-cut test: at 1000 random byte positions of a log being
// written, the file is cut (and the torn record scrambled, junk appended);
// recovery must return exactly the records completed before the cut.
#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pitvol/crc32c.h"
#include "pitvol/result_log.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using Bytes = std::vector<uint8_t>;

std::string make_temp_dir() {
  const char *base = std::getenv("TMPDIR");
  std::string templ = std::string(base && *base ? base : "/tmp") + "/pv-log-XXXXXX";
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back(0);
  if (!mkdtemp(buf.data())) return {};
  return buf.data();
}

void clear_dir(const std::string &dir) {
  if (DIR *d = opendir(dir.c_str())) {
    while (dirent *e = readdir(d))
      if (e->d_name[0] != '.') unlink((dir + "/" + e->d_name).c_str());
    closedir(d);
  }
}

void remove_dir(const std::string &dir) {
  clear_dir(dir);
  rmdir(dir.c_str());
}

std::string seg_path(const std::string &dir, uint32_t n) {
  char name[64];
  std::snprintf(name, sizeof name, "/seg-%08u.pvlog", n);
  return dir + name;
}

Bytes read_file(const std::string &path) {
  Bytes b;
  if (FILE *f = std::fopen(path.c_str(), "rb")) {
    int c;
    while ((c = std::fgetc(f)) != EOF) b.push_back(uint8_t(c));
    std::fclose(f);
  }
  return b;
}

void write_file(const std::string &path, const Bytes &b) {
  FILE *f = std::fopen(path.c_str(), "wb");
  assert_non_null(f);
  if (!b.empty()) assert_int_equal(std::fwrite(b.data(), 1, b.size(), f), b.size());
  std::fclose(f);
}

Bytes payload(pv::test::Rng &rng, size_t max_len) {
  Bytes p(1 + size_t(rng.next() % max_len));
  for (auto &b : p) b = uint8_t(rng.next());
  return p;
}

// Every record from from_seq on, as (seq, payload).
std::vector<std::pair<uint32_t, Bytes>> read_all(pv_log_t *log, uint32_t from_seq) {
  std::vector<std::pair<uint32_t, Bytes>> out;
  pv_log_cursor_t c;
  assert_int_equal(pv_log_seek(log, from_seq, &c), PV_LOG_OK);
  Bytes buf(PV_LOG_MAX_PAYLOAD_BYTES);
  uint32_t seq = 0;
  size_t len = 0;
  pv_log_status_t st;
  while ((st = pv_log_next(log, &c, buf.data(), buf.size(), &seq, &len)) == PV_LOG_OK)
    out.emplace_back(seq, Bytes(buf.begin(), buf.begin() + long(len)));
  assert_int_equal(st, PV_LOG_END);
  return out;
}

pv_log_config_t config(uint32_t segment_bytes, uint32_t max_segments) {
  pv_log_config_t c;
  pv_log_config_default(&c);
  c.segment_bytes = segment_bytes;
  c.max_segments = max_segments;
  return c;
}

// Storage damage, not a power cut: a byte of record 15 of 20 flips after
// all 20 were written (and sent to the host under their numbers).
// Recovery keeps 1..14 and must cut 15..20 with it, but their numbers stay
// used, across reboots too: the next result is 21, never 15 (the host
// already holds a 15).
void damaged_record_never_gives_its_number_again(void **) {
  const std::string dir = make_temp_dir();
  assert_false(dir.empty());
  pv::test::Rng rng{7};
  static pv_log_t log;
  const pv_log_config_t cfg = config(64 * 1024, 4);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  size_t at15 = 0, len15 = 0, offset = 0;
  for (uint32_t i = 1; i <= 20; ++i) {
    const Bytes p = payload(rng, 300);
    if (i == 15) {
      at15 = offset;
      len15 = p.size();
    }
    offset += PV_LOG_RECORD_BYTES(p.size());
    uint32_t seq = 0;
    assert_int_equal(pv_log_append(&log, p.data(), p.size(), &seq), PV_LOG_OK);
  }
  pv_log_close(&log);
  Bytes seg = read_file(seg_path(dir, 1));
  assert_int_equal(seg.size(), offset);
  seg[at15 + PV_LOG_HEADER_BYTES + len15 / 2] ^= 0x40;  // inside record 15's payload
  write_file(seg_path(dir, 1), seg);

  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  assert_int_equal(log.recovery.records, 14);
  assert_int_equal(log.recovery.records_lost, 5);  // 16..20, whole behind the damage
  assert_int_equal(log.recovery.torn_bytes, offset - at15);
  assert_int_equal(pv_log_last_seq(&log), 14);
  assert_int_equal(read_all(&log, 0).size(), 14);
  // A reboot before the next result: the cut bytes are gone from the
  // segment, the floor file keeps their numbers used.
  pv_log_close(&log);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  assert_int_equal(log.recovery.torn_bytes, 0);
  assert_int_equal(log.recovery.records_lost, 0);
  const Bytes next = payload(rng, 300);
  uint32_t seq = 0;
  assert_int_equal(pv_log_append(&log, next.data(), next.size(), &seq), PV_LOG_OK);
  assert_int_equal(seq, 21);
  pv_log_close(&log);
  // And after another reopen, 21 follows 14 and the next is 22.
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  auto all = read_all(&log, 0);
  assert_int_equal(all.size(), 15);
  assert_int_equal(all.back().first, 21);
  assert_true(all.back().second == next);
  assert_int_equal(pv_log_append(&log, next.data(), next.size(), &seq), PV_LOG_OK);
  assert_int_equal(seq, 22);
  pv_log_close(&log);
  remove_dir(dir);
}

// Garbage behind a torn tail that happens to check as a record (here made
// on purpose: magic, a number past 2^31 that no log reaches, CRC right)
// must not move the numbering towards a wrap: the next result is 4 after 3
// kept.
void checking_garbage_does_not_move_the_numbers(void **) {
  const std::string dir = make_temp_dir();
  assert_false(dir.empty());
  static pv_log_t log;
  const pv_log_config_t cfg = config(64 * 1024, 4);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  const uint8_t p[5] = {1, 2, 3, 4, 5};
  uint32_t seq = 0;
  for (int i = 0; i < 3; ++i) assert_int_equal(pv_log_append(&log, p, sizeof p, &seq), PV_LOG_OK);
  pv_log_close(&log);
  Bytes seg = read_file(seg_path(dir, 1));
  seg.push_back(0xEE);  // a torn byte
  const uint32_t fake[3] = {PV_LOG_RECORD_MAGIC, 0x90000000u, 0u};  // little-endian host
  Bytes rec(reinterpret_cast<const uint8_t *>(fake), reinterpret_cast<const uint8_t *>(fake) + 12);
  const uint32_t crc = pv_crc32c(0, rec.data(), rec.size());
  rec.insert(rec.end(), reinterpret_cast<const uint8_t *>(&crc), reinterpret_cast<const uint8_t *>(&crc) + 4);
  seg.insert(seg.end(), rec.begin(), rec.end());
  write_file(seg_path(dir, 1), seg);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  assert_int_equal(log.recovery.records, 3);
  assert_int_equal(log.recovery.records_lost, 0);
  assert_int_equal(log.recovery.torn_bytes, 17);
  assert_int_equal(pv_log_append(&log, p, sizeof p, &seq), PV_LOG_OK);
  assert_int_equal(seq, 4);
  pv_log_close(&log);
  remove_dir(dir);
}

void records_read_back_as_written_after_reopen(void **) {
  const std::string dir = make_temp_dir();
  assert_false(dir.empty());
  pv::test::Rng rng{1};
  std::vector<Bytes> written;
  static pv_log_t log;
  const pv_log_config_t cfg = config(64 * 1024, 4);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  assert_int_equal(pv_log_last_seq(&log), 0);
  for (uint32_t i = 1; i <= 50; ++i) {
    written.push_back(payload(rng, 300));
    uint32_t seq = 0;
    assert_int_equal(pv_log_append(&log, written.back().data(), written.back().size(), &seq),
                     PV_LOG_OK);
    assert_int_equal(seq, i);
  }
  pv_log_close(&log);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  assert_int_equal(log.recovery.records, 50);
  assert_int_equal(log.recovery.torn_bytes, 0);
  assert_int_equal(pv_log_first_seq(&log), 1);
  assert_int_equal(pv_log_last_seq(&log), 50);
  auto all = read_all(&log, 0);
  assert_int_equal(all.size(), 50);
  for (size_t i = 0; i < 50; ++i) {
    assert_int_equal(all[i].first, i + 1);
    assert_true(all[i].second == written[i]);
  }
  auto tail = read_all(&log, 20);
  assert_int_equal(tail.size(), 31);
  assert_int_equal(tail.front().first, 20);
  assert_true(read_all(&log, 51).empty());
  // The record on disk follows the documented layout.
  const Bytes file = read_file(seg_path(dir, 1));
  assert_memory_equal(file.data(), "PVR1", 4);
  assert_int_equal(file[4], 1);
  assert_int_equal(file[8], written[0].size() & 0xff);
  // Too large, bad settings.
  Bytes big(PV_LOG_MAX_PAYLOAD_BYTES + 1);
  assert_int_equal(pv_log_append(&log, big.data(), big.size(), nullptr), PV_LOG_ERR_TOO_LARGE);
  pv_log_close(&log);
  const pv_log_config_t tiny = config(100, 4);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &tiny), PV_LOG_ERR_INVALID_ARGUMENT);
  remove_dir(dir);
}

void rotation_keeps_the_log_bounded_and_the_newest_records(void **) {
  const std::string dir = make_temp_dir();
  static pv_log_t log;
  const pv_log_config_t cfg = config(2048, 3);
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  pv_log_cursor_t early;
  Bytes p(100, 0x42);
  for (uint32_t i = 1; i <= 200; ++i) {
    p[0] = uint8_t(i);
    assert_int_equal(pv_log_append(&log, p.data(), p.size(), nullptr), PV_LOG_OK);
    if (i == 5) assert_int_equal(pv_log_seek(&log, 1, &early), PV_LOG_OK);
  }
  // On disk: at most 3 segments of at most 2048 bytes.
  size_t files = 0, bytes = 0;
  DIR *d = opendir(dir.c_str());
  while (dirent *e = readdir(d)) {
    if (e->d_name[0] == '.') continue;
    files++;
    bytes += read_file(dir + "/" + e->d_name).size();
  }
  closedir(d);
  assert_true(files <= 3);
  assert_true(bytes <= 3 * 2048);
  const uint32_t first = pv_log_first_seq(&log);
  assert_true(first > 150);  // 116-byte records, 17 per segment
  assert_int_equal(pv_log_last_seq(&log), 200);
  // A cursor from before the rotation skips what was deleted.
  Bytes buf(PV_LOG_MAX_PAYLOAD_BYTES);
  uint32_t seq = 0;
  size_t len = 0;
  assert_int_equal(pv_log_next(&log, &early, buf.data(), buf.size(), &seq, &len), PV_LOG_OK);
  assert_int_equal(seq, first);
  assert_int_equal(buf[0], uint8_t(first));
  pv_log_close(&log);
  // Reopen: the same records, contiguous; appending continues the numbers.
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  const auto all = read_all(&log, 1);
  assert_int_equal(all.size(), 200 - first + 1);
  for (size_t i = 0; i < all.size(); ++i) assert_int_equal(all[i].first, first + i);
  assert_int_equal(pv_log_append(&log, p.data(), p.size(), &seq), PV_LOG_OK);
  assert_int_equal(seq, 201);
  pv_log_close(&log);
  remove_dir(dir);
}

// Where each record lives: segment number, byte range in it.
struct Placed {
  uint32_t segment;
  uint32_t start, end;
  Bytes payload;
};

void power_cut_at_1000_points_recovers_exactly_the_completed_records(void **) {
  const std::string dir = make_temp_dir(), cut_dir = make_temp_dir();
  pv::test::Rng rng{4242};
  static pv_log_t log;
  const pv_log_config_t cfg = config(4096, 64);  // several segments, none dropped
  assert_int_equal(pv_log_open(&log, dir.c_str(), &cfg), PV_LOG_OK);
  std::vector<Placed> recs;
  for (int i = 0; i < 60; ++i) {
    Bytes p = payload(rng, 400);
    const uint32_t start_seg = log.seg_count ? log.segs[log.seg_count - 1] : 0;
    const uint32_t start = log.active_bytes;
    assert_int_equal(pv_log_append(&log, p.data(), p.size(), nullptr), PV_LOG_OK);
    const uint32_t seg = log.segs[log.seg_count - 1];
    recs.push_back({seg, seg == start_seg ? start : 0, log.active_bytes, p});
  }
  const uint32_t segments = log.segs[log.seg_count - 1];
  assert_true(segments >= 3);
  pv_log_close(&log);
  std::vector<Bytes> images;
  for (uint32_t s = 1; s <= segments; ++s) images.push_back(read_file(seg_path(dir, s)));

  // Global byte positions: segment images one after the other.
  std::vector<size_t> seg_base(segments + 1, 0);
  for (uint32_t s = 1; s <= segments; ++s) seg_base[s] = s == 1 ? 0 : seg_base[s - 1] + images[s - 2].size();
  const size_t total = seg_base[segments] + images[segments - 1].size();

  size_t torn_seen = 0;
  for (int cut = 0; cut < 1000; ++cut) {
    // The first cuts land on record boundaries (and at 0, at the end).
    size_t pos;
    if (cut < 60) pos = seg_base[recs[size_t(cut)].segment] + recs[size_t(cut)].end;
    else if (cut == 60) pos = 0;
    else pos = size_t(rng.next() % (total + 1));
    // The record being written at pos (k == recs.size(): none).
    size_t k = 0;
    while (k < recs.size() && seg_base[recs[k].segment] + recs[k].end <= pos) ++k;
    clear_dir(cut_dir);
    const uint32_t cut_seg = k < recs.size() ? recs[k].segment : segments;
    for (uint32_t s = 1; s < cut_seg; ++s) write_file(seg_path(cut_dir, s), images[s - 1]);
    Bytes torn(images[cut_seg - 1].begin(),
               images[cut_seg - 1].begin() + long(std::min(pos - seg_base[cut_seg], images[cut_seg - 1].size())));
    if (k < recs.size()) {
      // The record in flight: some of its written bytes are wrong too.
      if (rng.next() % 2)
        for (size_t b = recs[k].start; b < torn.size(); ++b)
          if (rng.next() % 4 == 0) torn[b] = uint8_t(rng.next());
      // Junk past the cut (a sector written out of order).
      for (size_t j = rng.next() % 64; j > 0; --j) torn.push_back(uint8_t(rng.next()));
    }
    // A segment cut at byte 0 may not exist at all.
    if (!(torn.empty() && cut_seg > 1 && rng.next() % 2)) write_file(seg_path(cut_dir, cut_seg), torn);

    assert_int_equal(pv_log_open(&log, cut_dir.c_str(), &cfg), PV_LOG_OK);
    if (log.recovery.torn_bytes) torn_seen++;
    assert_int_equal(log.recovery.records, k);
    assert_int_equal(pv_log_last_seq(&log), k);
    const auto got = read_all(&log, 1);
    assert_int_equal(got.size(), k);
    for (size_t i = 0; i < k; ++i) {
      assert_int_equal(got[i].first, i + 1);
      assert_true(got[i].second == recs[i].payload);
    }
    // Every 10th cut: the log goes on after recovery.
    if (cut % 10 == 0) {
      const Bytes next = {1, 2, 3};
      uint32_t seq = 0;
      assert_int_equal(pv_log_append(&log, next.data(), next.size(), &seq), PV_LOG_OK);
      assert_int_equal(seq, k + 1);
      pv_log_close(&log);
      assert_int_equal(pv_log_open(&log, cut_dir.c_str(), &cfg), PV_LOG_OK);
      assert_int_equal(log.recovery.torn_bytes, 0);
      const auto again = read_all(&log, 1);
      assert_int_equal(again.size(), k + 1);
      assert_true(again.back().second == next);
    }
    pv_log_close(&log);
  }
  assert_true(torn_seen > 800);  // most cuts did tear a record
  remove_dir(dir);
  remove_dir(cut_dir);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(records_read_back_as_written_after_reopen),
      cmocka_unit_test(rotation_keeps_the_log_bounded_and_the_newest_records),
      cmocka_unit_test(power_cut_at_1000_points_recovers_exactly_the_completed_records),
      cmocka_unit_test(damaged_record_never_gives_its_number_again),
      cmocka_unit_test(checking_garbage_does_not_move_the_numbers),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
