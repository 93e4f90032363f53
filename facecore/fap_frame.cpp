#include "facecore/fap_frame.hpp"

namespace rostro {

void FapFrame::set(int id, double value) {
  const auto i = static_cast<std::size_t>(id - 1);
  mask.set(i);
  values[i] = value;
}

void FapFrame::clear(int id) {
  const auto i = static_cast<std::size_t>(id - 1);
  mask.reset(i);
  values[i] = 0.0;
}

void FapFrame::set_viseme(const VisemeParams& v) {
  mask.set(kVisemeFap - 1);
  viseme = v;
}

void FapFrame::set_expression(const ExpressionParams& e) {
  mask.set(kExpressionFap - 1);
  expression = e;
}

}  // namespace rostro
