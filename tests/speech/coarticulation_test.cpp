// The seed003 planner on its worked examples and the timing defects the notes document.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "speech/coarticulation.hpp"
#include "speech/key_sampler.hpp"
#include "speech_test_util.hpp"

namespace rostro::speech {
namespace {

struct Expected {
  std::string label;
  double ms;
};

void expect_keys(const std::vector<Key>& keys, const std::vector<Phoneme>& p,
                 const std::vector<Expected>& want) {
  ASSERT_EQ(keys.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(key_label(keys[i], p), want[i].label) << "key " << i;
    EXPECT_NEAR(keys[i].time_s * 1000.0, want[i].ms, 1e-9) << "key " << i << " " << want[i].label;
  }
}

TEST(Coarticulation, AffluenceGivesTheKeyInstantsOfTheNotes) {
  const auto p = test::affluence();
  const auto keys = plan_keys(p);
  // seed003-notes 4.2: neutral 100, { 260, {f 320, fu 420, lu 480, u 535, @ 620, @n 650, @s 720,
  // neutral 940.
  expect_keys(keys, p,
              {{"#", 100},
               {"{", 260},
               {"{f", 320},
               {"fu", 420},
               {"lu", 480},
               {"u", 535},
               {"@", 620},
               {"@n", 650},
               {"@s", 720},
               {"#", 940}});
  EXPECT_EQ(keys[3].kind, KeyKind::ConsonantVowel);  // f->l: first consonant + following vowel
  EXPECT_EQ(keys[8].kind, KeyKind::VowelConsonant);  // n->s: preceding vowel + current consonant
  // Sum of the patent's intervals = total - half of each edge silence.
  EXPECT_NEAR((keys.back().time_s - keys.front().time_s) * 1000.0, 1040.0 - 100.0 - 100.0, 1e-9);
}

TEST(Coarticulation, BackwardCaseCanUseTheFirstConsonantAsClaimFiveSays) {
  const auto p = test::affluence();
  PlannerOptions options;
  options.backward = BackwardConsonant::First;
  EXPECT_EQ(key_label(plan_keys(p, options)[8], p), "@n");
}

TEST(Coarticulation, WordInitialClusterHasNoDuplicateKey) {
  const auto p = test::street();
  const auto keys = plan_keys(p);
  // seed003-notes 4.4 with the fix: (s,i:) 300, (t,i:) 350, (r,i:) 410, i: 485, (i:,t) 560, neutral
  // 740.
  expect_keys(keys, p,
              {{"#", 100},
               {"si:", 300},
               {"ti:", 350},
               {"ri:", 410},
               {"i:", 485},
               {"i:t", 560},
               {"#", 740}});
  std::set<std::pair<std::string, double>> seen;
  for (const Key& k : keys)
    EXPECT_TRUE(seen.insert({key_label(k, p), k.time_s}).second) << key_label(k, p);
  EXPECT_NEAR((keys.back().time_s - keys.front().time_s) * 1000.0, 640.0, 1e-9);
}

TEST(Coarticulation, AffluenceFrameWeightsMatchAbsoluteTimeSampling) {
  const auto p = test::affluence();
  const auto keys = plan_keys(p);
  const auto frames = sample_keys(keys, frame_count_for(1.04, 25.0), 25.0);
  ASSERT_EQ(frames.size(), 26u);
  const auto weight_of = [&](long k, const std::string& label) {
    const FrameBlend& f = frames[static_cast<std::size_t>(k)];
    double w = 0.0;
    if (f.from < 0 && label == "#") w += 1.0 - f.weight;  // before the first key: neutral
    if (f.from >= 0 && key_label(keys[static_cast<std::size_t>(f.from)], p) == label)
      w += 1.0 - f.weight;
    if (f.to >= 0 && key_label(keys[static_cast<std::size_t>(f.to)], p) == label) w += f.weight;
    return w;
  };
  // seed003-notes 4.3.
  EXPECT_NEAR(weight_of(3, "{"), 0.125, 1e-9);   // t = 120
  EXPECT_NEAR(weight_of(7, "{"), 0.667, 1e-3);   // t = 280
  EXPECT_NEAR(weight_of(8, "{f"), 1.0, 1e-9);    // t = 320
  EXPECT_NEAR(weight_of(9, "fu"), 0.4, 1e-9);    // t = 360
  EXPECT_NEAR(weight_of(12, "lu"), 1.0, 1e-9);   // t = 480
  EXPECT_NEAR(weight_of(14, "@"), 0.294, 1e-3);  // t = 560
  EXPECT_NEAR(weight_of(16, "@n"), 0.667,
              1e-3);  // t = 640: the 30 ms @->n interval, no division by zero
  EXPECT_NEAR(weight_of(17, "@s"), 0.429, 1e-3);  // t = 680
  EXPECT_NEAR(weight_of(19, "@s"), 0.818, 1e-3);  // t = 760
  EXPECT_NEAR(weight_of(24, "#"), 1.0, 1e-9);     // t = 960
  for (long k = 0; k <= 2; ++k)
    EXPECT_NEAR(weight_of(k, "#"), 1.0, 1e-9) << "neutral until mid-silence";
  for (const FrameBlend& f : frames) {
    EXPECT_GE(f.weight, 0.0);
    EXPECT_LE(f.weight, 1.0);
  }
}

TEST(Coarticulation, ZeroLengthIntervalsNeverDivideByZero) {
  // Two keys at the same instant (a 0 ms phoneme) and an interval far below one frame.
  const auto p = test::phonemes({{"_", 's', 0, 100},
                                 {"a", 'v', 10, 0},
                                 {"p", 'c', 1, 3},
                                 {"a", 'v', 10, 90},
                                 {"_", 's', 0, 100}});
  const auto keys = plan_keys(p);
  for (std::size_t i = 1; i < keys.size(); ++i) EXPECT_LE(keys[i - 1].time_s, keys[i].time_s);
  const auto frames = sample_keys(keys, frame_count_for(0.293, 100.0), 100.0);
  for (const FrameBlend& f : frames) {
    EXPECT_TRUE(std::isfinite(f.weight));
    EXPECT_GE(f.weight, 0.0);
    EXPECT_LE(f.weight, 1.0);
  }
}

TEST(Coarticulation, VowellessWordAndNoSilenceAtEdges) {
  // "hmm" with no surrounding silence: context-free consonant keys, neutral at both ends.
  const auto p = test::phonemes({{"h", 'c', 5, 80}, {"m", 'c', 1, 200}});
  const auto keys = plan_keys(p);
  ASSERT_EQ(keys.size(), 4u);
  EXPECT_EQ(keys.front().kind, KeyKind::Neutral);
  EXPECT_EQ(keys[1].kind, KeyKind::Consonant);
  EXPECT_NEAR(keys[2].time_s, 0.180, 1e-12);
  EXPECT_EQ(keys.back().kind, KeyKind::Neutral);
  EXPECT_NEAR(keys.back().time_s, 0.280, 1e-12);
}

// A minute of varied syllables with awkward durations: every key sits exactly on its anchor,
// and the last key shows at full weight within one frame of its phoneme.
TEST(Coarticulation, NoDriftOverSixtySeconds) {
  std::vector<test::Spec> specs{{"_", 's', 0, 150}};
  const char* cons[] = {"p", "t", "k", "s", "m", "l", "r", "f"};
  const int cvis[] = {1, 4, 5, 7, 1, 8, 9, 2};
  const char* vows[] = {"a", "e", "i", "o", "u"};
  const int vvis[] = {10, 11, 12, 13, 14};
  double total = 150;
  for (int i = 0; total < 60000.0; ++i) {
    const double cd = 31.7 + (i * 7) % 53, vd = 57.3 + (i * 11) % 71;
    specs.push_back({cons[i % 8], 'c', cvis[i % 8], cd});
    specs.push_back({vows[i % 5], 'v', vvis[i % 5], vd});
    total += cd + vd;
    if (i % 9 == 8) {
      specs.push_back({"_", 's', 0, 173.3});
      total += 173.3;
    }
  }
  specs.push_back({"_", 's', 0, 200});
  total += 200;
  const auto p = test::phonemes(specs);
  const auto keys = plan_keys(p);
  for (const Key& k : keys) {
    if (k.kind == KeyKind::Vowel) {
      const Phoneme& v = p[static_cast<std::size_t>(k.vowel)];
      EXPECT_DOUBLE_EQ(k.time_s, v.start_s + v.duration() / 2);
    }
  }
  const double fps = 25.0;
  const long n = frame_count_for(total / 1000.0, fps);
  EXPECT_NEAR(static_cast<double>(n), total / 1000.0 * fps, 1.0);
  const auto frames = sample_keys(keys, n, fps);
  // The last vowel key: its full-weight frame is within one frame of the vowel's centre.
  int last = -1;
  for (int i = 0; i < static_cast<int>(keys.size()); ++i)
    if (keys[static_cast<std::size_t>(i)].kind == KeyKind::Vowel) last = i;
  ASSERT_GE(last, 0);
  long best = -1;
  double best_w = -1;
  for (long k = 0; k < n; ++k) {
    const FrameBlend& f = frames[static_cast<std::size_t>(k)];
    const double w = (f.from == last ? 1.0 - f.weight : 0.0) + (f.to == last ? f.weight : 0.0);
    if (w > best_w) best_w = w, best = k;
  }
  const Phoneme& v = p[static_cast<std::size_t>(keys[static_cast<std::size_t>(last)].vowel)];
  EXPECT_GT(v.start_s, 59.0);
  EXPECT_LE(std::abs(static_cast<double>(best) / fps - (v.start_s + v.duration() / 2)), 1.0 / fps);
}

}  // namespace
}  // namespace rostro::speech
