#pragma once
// Facial Expression Generation (seed004 6.3): the scripted expressions as one FAP layer.
// Each expression is its library vector (data/expressions.json) times intensity times an
// envelope that ramps linearly (or with a smoothstep ease) from 0 to 1 over ramp_in, holds,
// and ramps back over ramp_out. Overlapping expressions mix in proportion to their weights;
// where the weights add up to more than 1 they are scaled to sum to 1, so a cross-fade or two
// expressions at once never push a FAP past the stronger expression's own value.

#include <vector>

#include "facecore/expression_library.hpp"
#include "script/storyboard.hpp"
#include "speech/key_shapes.hpp"

namespace rostro::script {

using speech::FapVector;

class ExpressionTrack {
 public:
  ExpressionTrack(std::vector<ExpressionItem> items, const ExpressionLibrary& library);

  // The layer at time t (`value`) and, per FAP, how much expression acts on it (0..1: the
  // summed weight of the expressions that move that FAP), which FAP Synchronization uses.
  void sample(double t, FapVector& value, FapVector& activity) const;
  // One expression's weight at t: intensity x envelope.
  static double weight(const ExpressionItem& item, double t);

  bool empty() const { return items_.empty(); }
  // The FAPs some scripted expression moves.
  std::vector<int> faps() const;

 private:
  std::vector<ExpressionItem> items_;    // by start time
  std::vector<double> ended_by_;         // max end over items_[0..i]: skips finished ones
  std::vector<FapVector> vectors_;       // library vector of each item
  std::vector<std::vector<int>> moves_;  // FAPs each item moves
};

}  // namespace rostro::script
