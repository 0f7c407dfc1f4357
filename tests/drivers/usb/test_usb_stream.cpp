// USB frame stream reassembler (drivers/usb/usb_stream.c). The truth is
// built independently: the tests encode frames themselves with
// pv_usb_frame_encode, damage, drop, repeat or pad them in known ways, and
// know exactly which points must come out and what every counter must say.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "pitvol/usb_stream.h"
#include "test_rng.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

using pv::test::Rng;

static_assert(sizeof(pv_point_t) == 3 * sizeof(float), "pv_point_t is x, y, z packed");

constexpr float kMaxAbs = 1.0e6f;

struct Frame {
  pv_usb_frame_header_t h{};
  std::vector<float> xyz;  // 3 * point_count
  std::vector<uint8_t> bytes;
};

float coord(Rng &rng) { return float((rng.uniform() - 0.5) * 10000.0); }

Frame make_frame(uint32_t seq, const std::vector<float> &xyz, uint8_t flags = 0) {
  Frame f;
  f.h = {PV_USB_FRAME_VERSION, flags, uint16_t(xyz.size() / 3), seq, 1000000ull + 5000ull * seq};
  f.xyz = xyz;
  f.bytes.resize(PV_USB_FRAME_BYTES(f.h.point_count));
  const size_t n = pv_usb_frame_encode(f.bytes.data(), f.bytes.size(), &f.h, f.xyz.data());
  assert_int_equal(n, f.bytes.size());
  return f;
}

Frame random_frame(Rng &rng, uint32_t seq, uint16_t count, uint8_t flags = 0) {
  std::vector<float> xyz(3 * size_t(count));
  for (auto &v : xyz) v = coord(rng);
  return make_frame(seq, xyz, flags);
}

uint16_t random_count(Rng &rng, uint32_t max) { return uint16_t(rng.next() % (max + 1)); }

void append(std::vector<uint8_t> &out, const std::vector<uint8_t> &b) {
  out.insert(out.end(), b.begin(), b.end());
}

struct Got {
  uint32_t seq;
  uint8_t flags;
  std::vector<pv_point_t> pts;
};

struct Sink {
  std::vector<Got> frames;
};

void collect(void *user, const pv_usb_frame_header_t *h, const pv_point_t *p, size_t n) {
  auto *sink = static_cast<Sink *>(user);
  sink->frames.push_back({h->sequence, h->flags, std::vector<pv_point_t>(p, p + n)});
}

std::unique_ptr<pv_usb_stream_t> new_stream(Sink *sink, float max_abs = kMaxAbs) {
  std::unique_ptr<pv_usb_stream_t> s(new pv_usb_stream_t);
  pv_usb_stream_init(s.get(), max_abs, collect, sink);
  return s;
}

enum class Chunking { Whole, Random, Small, Bytewise };

// Feeds b in chunks; checks the buffer bound after every feed.
void feed_all(pv_usb_stream_t *s, const std::vector<uint8_t> &b, Chunking c, Rng &rng,
              size_t max_chunk = 70000) {
  size_t pos = 0;
  while (pos < b.size()) {
    size_t n = b.size() - pos;
    if (c == Chunking::Random) n = std::min(n, size_t(1 + rng.next() % max_chunk));
    if (c == Chunking::Small) n = std::min(n, size_t(1 + rng.next() % 100));
    if (c == Chunking::Bytewise) n = 1;
    pv_usb_stream_feed(s, b.data() + pos, n);
    assert_true(s->fill <= PV_USB_MAX_FRAME_BYTES);
    pos += n;
  }
}

// The callback saw exactly these frames, in order, their points bit for bit.
void expect_frames(const Sink &sink, const std::vector<const Frame *> &want) {
  assert_int_equal(sink.frames.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    const Got &g = sink.frames[i];
    const Frame &w = *want[i];
    assert_int_equal(g.seq, w.h.sequence);
    assert_int_equal(g.flags, w.h.flags);
    assert_int_equal(g.pts.size(), w.h.point_count);
    if (!g.pts.empty())
      assert_memory_equal(g.pts.data(), w.xyz.data(), g.pts.size() * sizeof(pv_point_t));
  }
}

#define PV_EXPECT_FIELD(f)                                                          \
  do {                                                                              \
    if (got.f != want.f) {                                                          \
      print_error("stats." #f ": got %llu, want %llu\n", (unsigned long long)got.f, \
                  (unsigned long long)want.f);                                      \
      bad = true;                                                                   \
    }                                                                               \
  } while (0)

void expect_stats(const pv_usb_stream_stats_t &got, const pv_usb_stream_stats_t &want) {
  bool bad = false;
  PV_EXPECT_FIELD(bytes_in);
  PV_EXPECT_FIELD(bytes_skipped);
  PV_EXPECT_FIELD(headers_bad);
  PV_EXPECT_FIELD(frames_ok);
  PV_EXPECT_FIELD(frames_bad_crc);
  PV_EXPECT_FIELD(frames_duplicate);
  PV_EXPECT_FIELD(sequence_gaps);
  PV_EXPECT_FIELD(frames_lost);
  PV_EXPECT_FIELD(points_ok);
  PV_EXPECT_FIELD(points_nonfinite);
  PV_EXPECT_FIELD(points_out_of_range);
  PV_EXPECT_FIELD(scans_ended);
  assert_false(bad);
}

bool same_stats(const pv_usb_stream_stats_t &a, const pv_usb_stream_stats_t &b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// ---------------------------------------------------------------------------

void clean_stream_arrives_whole_under_any_chunking(void **) {
  Rng rng{101};
  std::vector<Frame> frames;
  for (uint32_t i = 0; i < 500; ++i) {
    uint16_t n = random_count(rng, PV_USB_MAX_POINTS);
    if (i == 0) n = 0;
    if (i == 1) n = uint16_t(PV_USB_MAX_POINTS);
    frames.push_back(random_frame(rng, i, n));
  }
  for (Chunking c : {Chunking::Whole, Chunking::Random, Chunking::Bytewise}) {
    // One byte at a time for a smaller set (the first 40 frames).
    const size_t nf = c == Chunking::Bytewise ? 40 : frames.size();
    std::vector<uint8_t> stream;
    std::vector<const Frame *> want;
    pv_usb_stream_stats_t st{};
    for (size_t i = 0; i < nf; ++i) {
      append(stream, frames[i].bytes);
      want.push_back(&frames[i]);
      st.points_ok += frames[i].h.point_count;
    }
    st.bytes_in = stream.size();
    st.frames_ok = nf;
    Sink sink;
    auto s = new_stream(&sink);
    std::memset(s->frame, 0xA5, sizeof s->frame);
    feed_all(s.get(), stream, c, rng);
    expect_frames(sink, want);
    expect_stats(s->stats, st);
    assert_int_equal(s->fill, 0);
    if (c == Chunking::Whole) {
      // Whole frames are parsed in place: the frame buffer was never used.
      assert_true(std::all_of(s->frame, s->frame + sizeof s->frame,
                              [](uint8_t b) { return b == 0xA5; }));
    }
  }
}

void aligned_feeds_never_touch_the_frame_buffer(void **) {
  Rng rng{102};
  Sink sink;
  auto s = new_stream(&sink);
  std::memset(s->frame, 0xA5, sizeof s->frame);
  std::vector<Frame> frames;
  std::vector<const Frame *> want;
  for (uint32_t i = 0; i < 200; ++i) frames.push_back(random_frame(rng, i, random_count(rng, 600)));
  // Feeds of 1..5 whole frames each.
  for (size_t i = 0; i < frames.size();) {
    std::vector<uint8_t> chunk;
    const size_t k = std::min(frames.size() - i, size_t(1 + rng.next() % 5));
    for (size_t j = 0; j < k; ++j, ++i) {
      append(chunk, frames[i].bytes);
      want.push_back(&frames[i]);
    }
    pv_usb_stream_feed(s.get(), chunk.data(), chunk.size());
    assert_int_equal(s->fill, 0);
  }
  expect_frames(sink, want);
  assert_true(std::all_of(s->frame, s->frame + sizeof s->frame, [](uint8_t b) { return b == 0xA5; }));
}

// How a byte corruption at pos (xor v) is rejected: 1 = header, 0 = CRC.
bool rejected_as_header(const Frame &f, size_t pos, uint8_t v) {
  if (pos < 5) return true;                                   // magic, version
  if (pos == 5) return ((f.h.flags ^ v) & ~PV_USB_FLAGS_KNOWN) != 0;  // flags
  if (pos == 6 || pos == 7) {
    uint8_t b[2] = {f.bytes[6], f.bytes[7]};
    b[pos - 6] = uint8_t(b[pos - 6] ^ v);
    return (b[0] | b[1] << 8) > int(PV_USB_MAX_POINTS);
  }
  return false;
}

void corrupted_frames_are_rejected_and_swallow_nothing(void **) {
  Rng rng{103};
  const size_t nf = 500;
  std::vector<Frame> frames;
  for (uint32_t i = 0; i < nf; ++i) frames.push_back(random_frame(rng, i, random_count(rng, PV_USB_MAX_POINTS)));
  // Bytes after each frame: a frame whose corrupted count could claim more
  // than what follows would be left pending at the end of the test stream.
  std::vector<size_t> after(nf + 1, 0);
  for (size_t i = nf; i-- > 0;) after[i] = after[i + 1] + frames[i].bytes.size();

  std::vector<uint8_t> stream;
  std::vector<const Frame *> want;
  pv_usb_stream_stats_t st{};
  size_t corrupted = 0, kinds[8] = {};
  long last_clean = -1;
  for (size_t i = 0; i < nf; ++i) {
    Frame &f = frames[i];
    const bool corrupt = after[i + 1] >= PV_USB_MAX_FRAME_BYTES && rng.next() % 10 == 0;
    if (!corrupt) {
      append(stream, f.bytes);
      want.push_back(&f);
      st.frames_ok++;
      st.points_ok += f.h.point_count;
      if (last_clean >= 0 && size_t(last_clean) + 1 < i) {
        st.sequence_gaps++;
        st.frames_lost += i - size_t(last_clean) - 1;
      }
      last_clean = long(i);
      continue;
    }
    std::vector<uint8_t> b = f.bytes;
    size_t pos = 0;
    uint8_t v = 0;
    const size_t kind = corrupted % 8;
    switch (kind) {
      case 0:  // anywhere
        pos = size_t(rng.next() % b.size());
        v = uint8_t(1 + rng.next() % 255);
        break;
      case 1:  // count claims more (>= 3840 points, still a valid count)
      case 2:  // count claims less or other valid value
        pos = 7;
        v = uint8_t(b[7] ^ (kind == 1 && b[7] != 0x0f ? 0x0f : 0x00));
        if (v == 0) {  // high byte already as wanted: change the low byte
          pos = 6;
          v = 0x5a;
        }
        break;
      case 3:  // the CRC itself
        pos = b.size() - 1 - size_t(rng.next() % 4);
        v = uint8_t(1 + rng.next() % 255);
        break;
      case 4:  // magic
        pos = size_t(rng.next() % 4);
        v = uint8_t(1 + rng.next() % 255);
        break;
      case 5:  // version
        pos = 4;
        v = 0x02;
        break;
      case 6:  // count > PV_USB_MAX_POINTS
        pos = 7;
        v = uint8_t(b[7] ^ 0x20);
        break;
      default:  // sequence / timestamp / points
        pos = 8 + size_t(rng.next() % (b.size() - 12));
        v = uint8_t(1 + rng.next() % 255);
        break;
    }
    b[pos] = uint8_t(b[pos] ^ v);
    if (rejected_as_header(f, pos, v))
      st.headers_bad++;
    else
      st.frames_bad_crc++;
    st.bytes_skipped += b.size();
    append(stream, b);
    ++corrupted;
    ++kinds[kind];
  }
  st.bytes_in = stream.size();
  assert_true(corrupted >= 40);
  for (size_t k : kinds) assert_true(k >= 3);
  assert_true(st.headers_bad > 0 && st.frames_bad_crc > 0);
  assert_int_equal(st.headers_bad + st.frames_bad_crc, corrupted);

  pv_usb_stream_stats_t first{};
  for (Chunking c : {Chunking::Whole, Chunking::Random, Chunking::Small}) {
    Sink sink;
    auto s = new_stream(&sink);
    feed_all(s.get(), stream, c, rng);
    expect_frames(sink, want);
    expect_stats(s->stats, st);
    assert_int_equal(s->fill, 0);
    if (c == Chunking::Whole) first = s->stats;
    assert_true(same_stats(first, s->stats));
  }
}

void garbage_between_frames_is_skipped_and_counted(void **) {
  Rng rng{104};
  const size_t nf = 200;
  std::vector<Frame> frames;
  for (uint32_t i = 0; i < nf; ++i) frames.push_back(random_frame(rng, i, random_count(rng, 300)));

  std::vector<uint8_t> stream;
  std::vector<const Frame *> want;
  pv_usb_stream_stats_t st{};
  size_t kinds[4] = {};
  auto plain_garbage = [&](size_t n) {
    std::vector<uint8_t> g(n);
    for (auto &b : g) {
      b = uint8_t(rng.next());
      if (b == 'P') b = 'Q';  // no magic by accident
    }
    return g;
  };
  auto insert_at = [](std::vector<uint8_t> &g, size_t at, const std::vector<uint8_t> &x) {
    g.insert(g.begin() + long(at), x.begin(), x.end());
  };
  auto add_garbage = [&](size_t kind) {
    std::vector<uint8_t> g = plain_garbage(1 + rng.next() % 300);
    const size_t at = 1 + rng.next() % g.size();  // never at the start
    st.headers_bad++;  // the garbage itself: one resynchronisation
    if (kind == 1) {   // a fake magic with a bad version: a second one
      insert_at(g, at, {'P', 'V', 'F', '1', 7});
      st.headers_bad++;
    } else if (kind == 2 || kind == 3) {
      // A fake header that parses; kind 2: a whole 0-point frame with a
      // wrong CRC; kind 3: only the header, claiming 4000 points, so the
      // real frames after it are taken in until its CRC fails, then found.
      pv_usb_frame_header_t h{PV_USB_FRAME_VERSION, 0, uint16_t(kind == 2 ? 0 : 4000),
                              uint32_t(rng.next()), 0};
      std::vector<uint8_t> fake(PV_USB_FRAME_BYTES(h.point_count));
      std::vector<float> pts(3 * size_t(h.point_count), 1.0f);
      assert_int_equal(pv_usb_frame_encode(fake.data(), fake.size(), &h, pts.data()), fake.size());
      fake.back() ^= 0x01;
      fake.resize(kind == 2 ? fake.size() : PV_USB_HEADER_BYTES);
      insert_at(g, at, fake);
      st.frames_bad_crc++;
    }
    st.bytes_skipped += g.size();
    append(stream, g);
    kinds[kind]++;
  };
  add_garbage(0);  // before the first frame
  for (size_t i = 0; i < nf; ++i) {
    append(stream, frames[i].bytes);
    want.push_back(&frames[i]);
    st.frames_ok++;
    st.points_ok += frames[i].h.point_count;
    if (i + 1 < nf && rng.next() % 10 < 3) {
      size_t kind = size_t(rng.next() % 4);
      if (kind == 3 && i > nf / 2) kind = 2;  // leave room for 4000 claimed points
      add_garbage(kind);
    }
  }
  add_garbage(0);  // trailing garbage
  st.bytes_in = stream.size();
  for (size_t k : kinds) assert_true(k >= 3);

  for (Chunking c : {Chunking::Whole, Chunking::Random, Chunking::Small}) {
    Sink sink;
    auto s = new_stream(&sink);
    feed_all(s.get(), stream, c, rng, 5000);
    expect_frames(sink, want);
    expect_stats(s->stats, st);
    assert_int_equal(s->fill, 0);
  }
}

void lost_and_duplicated_frames_are_counted_exactly(void **) {
  Rng rng{105};
  const uint32_t nf = 1000;
  std::vector<Frame> frames;
  for (uint32_t i = 0; i < nf; ++i) frames.push_back(random_frame(rng, i, random_count(rng, 32)));
  std::vector<uint8_t> stream;
  std::vector<const Frame *> want;
  pv_usb_stream_stats_t st{};
  bool in_gap = false;
  for (uint32_t i = 0; i < nf; ++i) {
    if (i > 0 && i + 1 < nf && rng.next() % 20 == 0) {  // dropped on the way
      st.frames_lost++;
      if (!in_gap) st.sequence_gaps++;
      in_gap = true;
      continue;
    }
    in_gap = false;
    append(stream, frames[i].bytes);
    want.push_back(&frames[i]);
    st.frames_ok++;
    st.points_ok += frames[i].h.point_count;
    if (rng.next() % 20 == 0) {  // the same frame again, or an earlier delivered one
      const size_t back = size_t(rng.next() % std::min<size_t>(want.size(), 20));
      const Frame *again = want[want.size() - 1 - back];
      // Not a late frame 0: sequence 0 without END_OF_SCAN before it
      // starts a new scan (usb_stream.h), see sequence_window_and_scan_edges.
      if (again->h.sequence != 0 || back == 0) {
        append(stream, again->bytes);
        st.frames_duplicate++;
      }
    }
  }
  st.bytes_in = stream.size();
  assert_true(st.frames_duplicate >= 20 && st.sequence_gaps >= 20);
  for (Chunking c : {Chunking::Whole, Chunking::Random, Chunking::Small}) {
    Sink sink;
    auto s = new_stream(&sink);
    feed_all(s.get(), stream, c, rng, 3000);
    expect_frames(sink, want);  // never called for a duplicate
    expect_stats(s->stats, st);
  }
}

void sequence_window_and_scan_edges(void **) {
  Rng rng{106};
  auto run = [&](const std::vector<std::pair<uint32_t, uint8_t>> &seqs) {
    Sink sink;
    auto s = new_stream(&sink);
    for (auto [seq, flags] : seqs) {
      Frame f = random_frame(rng, seq, 2, flags);
      pv_usb_stream_feed(s.get(), f.bytes.data(), f.bytes.size());
    }
    return std::make_pair(s->stats, sink.frames.size());
  };
  const uint8_t E = PV_USB_FLAG_END_OF_SCAN;
  {  // first frame sets the sequence, whatever it is
    auto [st, n] = run({{77, 0}, {78, 0}});
    assert_int_equal(n, 2);
    assert_int_equal(st.sequence_gaps, 0);
  }
  {  // window: exactly PV_USB_STREAM_DUP_WINDOW - 1 behind is a duplicate ...
    auto [st, n] = run({{5000, 0}, {5000 - PV_USB_STREAM_DUP_WINDOW + 1, 0}});
    assert_int_equal(n, 1);
    assert_int_equal(st.frames_duplicate, 1);
    assert_int_equal(st.sequence_gaps, 0);
  }
  {  // ... one further is a jump forward (modulo 2^32)
    auto [st, n] = run({{5000, 0}, {5000 - PV_USB_STREAM_DUP_WINDOW, 0}});
    assert_int_equal(n, 2);
    assert_int_equal(st.frames_duplicate, 0);
    assert_int_equal(st.sequence_gaps, 1);
    assert_true(st.frames_lost == uint64_t(uint32_t(0u - PV_USB_STREAM_DUP_WINDOW - 1u)));
  }
  {  // wrap-around is in order
    auto [st, n] = run({{0xFFFFFFFEu, 0}, {0xFFFFFFFFu, 0}, {0, 0}, {1, 0}});
    assert_int_equal(n, 4);
    assert_int_equal(st.sequence_gaps + st.frames_duplicate, 0);
  }
  {  // a repeated END_OF_SCAN frame is a duplicate; the next scan from 0
    auto [st, n] = run({{0, 0}, {1, E}, {1, E}, {0, 0}, {1, 0}});
    assert_int_equal(n, 4);
    assert_int_equal(st.frames_duplicate, 1);
    assert_int_equal(st.scans_ended, 1);
    assert_int_equal(st.sequence_gaps, 0);
  }
  {  // a new scan whose first frames were lost
    auto [st, n] = run({{0, 0}, {1, E}, {2, 0}, {3, 0}});
    assert_int_equal(n, 4);
    assert_int_equal(st.sequence_gaps, 1);
    assert_int_equal(st.frames_lost, 2);
  }
  {  // 0 without END_OF_SCAN before it (scanner restarted): a new scan, no gap
    auto [st, n] = run({{0, 0}, {1, 0}, {2, 0}, {0, 0}, {1, 0}});
    assert_int_equal(n, 5);
    assert_int_equal(st.sequence_gaps + st.frames_duplicate + st.frames_lost, 0);
  }
  {  // but frame 0 twice in a row is a duplicate
    auto [st, n] = run({{0, 0}, {0, 0}, {1, 0}});
    assert_int_equal(n, 2);
    assert_int_equal(st.frames_duplicate, 1);
  }
}

void end_of_scan_then_a_new_scan_counts_no_gap(void **) {
  Rng rng{107};
  std::vector<Frame> frames;
  const uint32_t lens[3] = {10, 5, 3};
  for (int scan = 0; scan < 3; ++scan)
    for (uint32_t i = 0; i < lens[scan]; ++i)
      frames.push_back(random_frame(rng, i, random_count(rng, 100),
                                    uint8_t(scan < 2 && i + 1 == lens[scan] ? PV_USB_FLAG_END_OF_SCAN : 0)));
  std::vector<uint8_t> stream;
  std::vector<const Frame *> want;
  pv_usb_stream_stats_t st{};
  for (const Frame &f : frames) {
    append(stream, f.bytes);
    want.push_back(&f);
    st.points_ok += f.h.point_count;
  }
  st.bytes_in = stream.size();
  st.frames_ok = frames.size();
  st.scans_ended = 2;
  for (Chunking c : {Chunking::Whole, Chunking::Small}) {
    Sink sink;
    auto s = new_stream(&sink);
    feed_all(s.get(), stream, c, rng);
    expect_frames(sink, want);
    expect_stats(s->stats, st);
  }
}

void nonfinite_and_far_points_are_dropped_and_counted(void **) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  // clang-format off
  const std::vector<float> xyz = {
      1.0f, 2.0f, 3.0f,         // kept
      nan, 0.0f, 0.0f,          // nonfinite
      -4.0f, 5.5f, 6.25f,       // kept
      0.0f, inf, 0.0f,          // nonfinite
      0.0f, 0.0f, -inf,         // nonfinite
      2.0e6f, 0.0f, 0.0f,       // out of range
      0.0f, 0.0f, -2.0e6f,      // out of range
      nan, 2.0e6f, 0.0f,        // nonfinite (checked first)
      1.0e6f, -1.0e6f, 1.0e6f,  // kept: the limit itself is in range
      -1.0e-30f, 0.0f, 999999.9f,  // kept
  };
  // clang-format on
  const std::vector<float> kept = {1.0f, 2.0f,    3.0f,    -4.0f,     5.5f, 6.25f,
                                   1.0e6f, -1.0e6f, 1.0e6f, -1.0e-30f, 0.0f, 999999.9f};
  Frame f = make_frame(0, xyz);
  Sink sink;
  auto s = new_stream(&sink, 1.0e6f);
  pv_usb_stream_feed(s.get(), f.bytes.data(), f.bytes.size());
  assert_int_equal(sink.frames.size(), 1);
  assert_int_equal(sink.frames[0].pts.size(), kept.size() / 3);
  assert_memory_equal(sink.frames[0].pts.data(), kept.data(), kept.size() * sizeof(float));
  pv_usb_stream_stats_t st{};
  st.bytes_in = f.bytes.size();
  st.frames_ok = 1;
  st.points_ok = 4;
  st.points_nonfinite = 4;
  st.points_out_of_range = 2;
  expect_stats(s->stats, st);
}

void drop_partial_discards_half_a_frame(void **) {
  Rng rng{108};
  const Frame a = random_frame(rng, 0, 300), b = random_frame(rng, 1, 3000),
              c = random_frame(rng, 2, 50);
  Sink sink;
  auto s = new_stream(&sink);
  assert_int_equal(pv_usb_stream_drop_partial(s.get()), 0);
  pv_usb_stream_feed(s.get(), a.bytes.data(), a.bytes.size());
  const size_t half = b.bytes.size() / 2;
  pv_usb_stream_feed(s.get(), b.bytes.data(), half);
  assert_int_equal(s->fill, half);
  assert_int_equal(pv_usb_stream_drop_partial(s.get()), half);
  assert_int_equal(s->fill, 0);
  assert_int_equal(s->stats.bytes_skipped, half);
  // The rest of b never comes; c does (in two pieces).
  pv_usb_stream_feed(s.get(), c.bytes.data(), 7);
  pv_usb_stream_feed(s.get(), c.bytes.data() + 7, c.bytes.size() - 7);
  expect_frames(sink, {&a, &c});
  pv_usb_stream_stats_t st{};
  st.bytes_in = a.bytes.size() + half + c.bytes.size();
  st.bytes_skipped = half;
  st.frames_ok = 2;
  st.points_ok = 350;
  st.sequence_gaps = 1;
  st.frames_lost = 1;
  expect_stats(s->stats, st);
  // A partial header, dropped, then nothing pending.
  pv_usb_stream_feed(s.get(), b.bytes.data(), 5);
  assert_int_equal(pv_usb_stream_drop_partial(s.get()), 5);
  assert_int_equal(pv_usb_stream_drop_partial(s.get()), 0);
  assert_int_equal(s->stats.bytes_skipped, half + 5);
}

void throughput_of_feed_in_64k_chunks(void **) {
  Rng rng{109};
  std::vector<uint8_t> stream;
  for (uint32_t i = 0; i < 400; ++i) append(stream, random_frame(rng, i, random_count(rng, PV_USB_MAX_POINTS)).bytes);
  std::unique_ptr<pv_usb_stream_t> s(new pv_usb_stream_t);
  uint64_t points = 0;
  auto count = [](void *user, const pv_usb_frame_header_t *, const pv_point_t *, size_t n) {
    *static_cast<uint64_t *>(user) += n;
  };
  const size_t chunk = 64 * 1024;
  double bytes = 0.0, seconds = 0.0;
  int reps = 0;
  while (seconds < 0.5 || reps < 2) {
    pv_usb_stream_init(s.get(), kMaxAbs, count, &points);
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t pos = 0; pos < stream.size(); pos += chunk)
      pv_usb_stream_feed(s.get(), stream.data() + pos, std::min(chunk, stream.size() - pos));
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    bytes += double(stream.size());
    assert_int_equal(s->stats.frames_ok, 400);
    ++reps;
  }
  std::printf("[ INFO     ] usb_stream feed: %.1f MB/s (64 KiB chunks, %.1f MB stream x %d)\n",
              bytes / seconds / 1e6, double(stream.size()) / 1e6, reps);
}

// --- fuzzing ---------------------------------------------------------------

struct FuzzSink {
  float lim;
  uint64_t frame_bytes;  // bytes of the frames delivered
  bool points_ok = true;
};

void fuzz_collect(void *user, const pv_usb_frame_header_t *h, const pv_point_t *p, size_t n) {
  auto *f = static_cast<FuzzSink *>(user);
  f->frame_bytes += PV_USB_FRAME_BYTES(h->point_count);
  if (n > h->point_count) f->points_ok = false;
  for (size_t i = 0; i < n; ++i)
    for (float v : {p[i].x_mm, p[i].y_mm, p[i].z_mm})
      if (!std::isfinite(v) || std::fabs(v) > f->lim) f->points_ok = false;
}

size_t count_magic(const uint8_t *d, size_t n) {
  size_t k = 0;
  for (size_t i = 0; i + 4 <= n; ++i)
    if (d[i] == 'P' && d[i + 1] == 'V' && d[i + 2] == 'F' && d[i + 3] == '1') ++k;
  return k;
}

// libFuzzer-style entry: any bytes, any chunking, no crash, invariants hold.
// (Build with -fsanitize=fuzzer and call from LLVMFuzzerTestOneInput to
// run it under a real fuzzer; here a deterministic loop drives it.)
void fuzz_one(pv_usb_stream_t *s, const uint8_t *data, size_t size, Rng &rng) {
  FuzzSink sink{1000.0f, 0};
  pv_usb_stream_init(s, sink.lim, fuzz_collect, &sink);
  size_t pos = 0, dropped = 0;
  while (pos < size) {
    const size_t n = std::min(size - pos, size_t(1 + rng.next() % (rng.next() % 2 ? 64 : 4096)));
    pv_usb_stream_feed(s, data + pos, n);
    pos += n;
    assert_true(s->fill <= PV_USB_MAX_FRAME_BYTES);
    if (rng.next() % 64 == 0) dropped += pv_usb_stream_drop_partial(s);
  }
  const pv_usb_stream_stats_t &st = s->stats;
  assert_true(sink.points_ok);
  assert_int_equal(st.bytes_in, size);
  assert_true(st.frames_ok + st.frames_bad_crc + st.frames_duplicate <= count_magic(data, size));
  assert_true(st.bytes_skipped >= dropped);
  // Every byte is skipped, in a frame or pending.
  if (st.frames_duplicate == 0)
    assert_int_equal(st.bytes_skipped + sink.frame_bytes + s->fill, st.bytes_in);
  else
    assert_true(st.bytes_skipped + sink.frame_bytes + s->fill <= st.bytes_in);
  assert_true(st.points_ok + st.points_nonfinite + st.points_out_of_range <=
              st.frames_ok * PV_USB_MAX_POINTS);
  assert_true(st.frames_lost >= st.sequence_gaps);
}

void fuzz_harness_holds_its_invariants(void **) {
  Rng rng{110};
  std::unique_ptr<pv_usb_stream_t> s(new pv_usb_stream_t);
  const uint8_t alphabet[] = {'P', 'V', 'F', '1', 0x00, 0x01, 0x10, 0xff};
  const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(), -2.0e6f, 999.0f, -1000.0f};
  std::vector<uint8_t> data;
  for (int iter = 0; iter < 20000; ++iter) {
    data.clear();
    if (iter % 2 == 0) {  // random bytes, rich in magic pieces
      const size_t n = size_t(rng.next() % 3000);
      for (size_t i = 0; i < n; ++i) {
        const uint64_t r = rng.next();
        if (r % 16 == 0 && i + 4 <= n) {
          for (uint8_t b : {'P', 'V', 'F', '1'}) data.push_back(b);
          i += 3;
        } else {
          data.push_back(r % 3 == 0 ? alphabet[(r >> 8) % sizeof alphabet] : uint8_t(r >> 16));
        }
      }
    } else {  // a valid stream, mutated
      const uint32_t nfr = uint32_t(1 + rng.next() % 8);
      uint32_t seq = uint32_t(rng.next() % 4);
      for (uint32_t k = 0; k < nfr; ++k) {
        const uint16_t cnt = rng.next() % 40 == 0 ? uint16_t(PV_USB_MAX_POINTS) : random_count(rng, 60);
        std::vector<float> xyz(3 * size_t(cnt));
        for (auto &v : xyz) v = rng.next() % 10 == 0 ? specials[rng.next() % 5] : float(rng.uniform() * 1800.0 - 900.0);
        const uint32_t sq = rng.next() % 8 == 0 ? uint32_t(rng.next() % 3) : seq++;
        append(data, make_frame(sq, xyz, uint8_t(rng.next() % 6 == 0)).bytes);
      }
      const int muts = int(rng.next() % 6);
      for (int m = 0; m < muts && !data.empty(); ++m) {
        const size_t at = size_t(rng.next() % data.size());
        switch (rng.next() % 7) {
          case 0: data[at] = uint8_t(data[at] ^ (1u << (rng.next() % 8))); break;
          case 1: data[at] = uint8_t(rng.next()); break;
          case 2: {  // insert random bytes
            std::vector<uint8_t> ins(size_t(1 + rng.next() % 64));
            for (auto &b : ins) b = uint8_t(rng.next());
            data.insert(data.begin() + long(at), ins.begin(), ins.end());
            break;
          }
          case 3: {  // delete a range
            const size_t n = std::min(data.size() - at, size_t(1 + rng.next() % 200));
            data.erase(data.begin() + long(at), data.begin() + long(at + n));
            break;
          }
          case 4: {  // duplicate a range
            const size_t n = std::min(data.size() - at, size_t(1 + rng.next() % 500));
            std::vector<uint8_t> dup(data.begin() + long(at), data.begin() + long(at + n));
            data.insert(data.begin() + long(at), dup.begin(), dup.end());
            break;
          }
          case 5: data.resize(at); break;  // truncate
          default: {  // a fake magic + random header bytes
            std::vector<uint8_t> ins = {'P', 'V', 'F', '1', 1, uint8_t(rng.next() % 2),
                                        uint8_t(rng.next()), uint8_t(rng.next() % 0x11)};
            data.insert(data.begin() + long(at), ins.begin(), ins.end());
            break;
          }
        }
      }
    }
    fuzz_one(s.get(), data.data(), data.size(), rng);
  }
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(clean_stream_arrives_whole_under_any_chunking),
      cmocka_unit_test(aligned_feeds_never_touch_the_frame_buffer),
      cmocka_unit_test(corrupted_frames_are_rejected_and_swallow_nothing),
      cmocka_unit_test(garbage_between_frames_is_skipped_and_counted),
      cmocka_unit_test(lost_and_duplicated_frames_are_counted_exactly),
      cmocka_unit_test(sequence_window_and_scan_edges),
      cmocka_unit_test(end_of_scan_then_a_new_scan_counts_no_gap),
      cmocka_unit_test(nonfinite_and_far_points_are_dropped_and_counted),
      cmocka_unit_test(drop_partial_discards_half_a_frame),
      cmocka_unit_test(throughput_of_feed_in_64k_chunks),
      cmocka_unit_test(fuzz_harness_holds_its_invariants),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
