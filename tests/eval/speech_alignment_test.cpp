// `rostro eval alignment` (eval/speech_alignment): its cases score what docs/accuracy.md
// says they score, within a margin for espeak-ng's call-to-call variation.

#include "eval/speech_alignment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace rostro::eval {
namespace {

AlignmentCase named(const std::string& name) {
  const auto cases = default_alignment_cases();
  const auto it = std::find_if(cases.begin(), cases.end(),
                               [&](const AlignmentCase& c) { return c.name == name; });
  EXPECT_NE(it, cases.end()) << name;
  return *it;
}

TEST(SpeechAlignmentEval, AnotherEspeakVoiceMeetsTheAims) {
  const AlignmentScore s = score_alignment(named("pt_female_noisy"));
  ASSERT_FALSE(s.skipped);
  EXPECT_GT(s.boundary_ms.count, 150u);
  EXPECT_LE(s.boundary_ms.median, 20.0);
  EXPECT_LE(s.boundary_ms.p95, 50.0);
  EXPECT_EQ(s.bilabials_late, 0);
  EXPECT_GT(s.bilabials, 10);
  EXPECT_GT(s.shape_agreement, 0.9);
  EXPECT_LT(s.match_ratio, s.wrong_text_ratio);
}

// flite is a second synthesiser with its own phone set and timing: the alignment misses the
// boundary aims there (docs/accuracy.md) but keeps every bilabial within a frame, and
// PocketSphinx, with no transcript, finds most bilabials of its clustergen voices.
TEST(SpeechAlignmentEval, FliteVoiceAsDocumented) {
  const AlignmentScore s = score_alignment(named("en_flite_slt"));
  if (s.skipped) GTEST_SKIP() << s.skip_reason;
  EXPECT_LE(s.boundary_ms.median, 20.0);
  EXPECT_LE(s.boundary_ms.p95, 100.0);
  EXPECT_EQ(s.bilabials_late, 0);
  ASSERT_TRUE(s.recognised);
  EXPECT_GE(s.recognised_bilabials_found, s.bilabials * 7 / 10);
  EXPECT_GT(s.recognised_shape_agreement, 0.6);
}

TEST(SpeechAlignmentEval, TableHasARowPerCaseAndTheAims) {
  AlignmentScore skipped;
  skipped.name = "x";
  skipped.skipped = true;
  skipped.skip_reason = "flite is not installed";
  const std::string table = alignment_table({skipped});
  EXPECT_NE(table.find("| x | skipped: flite is not installed"), std::string::npos);
  EXPECT_NE(table.find("Aims (issue 20)"), std::string::npos);
}

}  // namespace
}  // namespace rostro::eval
