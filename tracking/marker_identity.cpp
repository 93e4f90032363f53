// Checking the names during the take: the second look at a fresh naming after the start,
// and the followed dots named again from their places while any name is unconfirmed.
#include "tracking/marker_tracker_impl.hpp"

namespace rostro::tracking {

bool MarkerTracker::Impl::second_look(long frame) {
  ensure_gray({0, 0, gray.cols, gray.rows});
  const Identification id = name_frame(detect_all_tags());
  if (!id.confidence.confident) {
    moved_before.clear();
    return false;
  }
  std::vector<std::string> moved;
  for (size_t i = 0; i < states.size(); ++i) {
    const auto named = id.dots.find(states[i].spec->id);
    if (!states[i].valid || named == id.dots.end()) continue;
    if (cv::norm(named->second.center - states[i].position) > 0.5 * spacing[i] * face_scale)
      moved.push_back(states[i].spec->id);
  }
  const bool confirmed = !moved.empty() && moved == moved_before;
  moved_before = moved;
  // (A start on a frame a fading blur still smears is sure for a wrong reason:
  // TrackerOptions::second_look_tries.)
  const bool as_sure = id.confidence.margin + kMarginNoise >= identification.margin &&
                       id.confidence.matched + kMatchedNoise >= identification.matched;
  if (moved.empty()) {
    if (!as_sure) return false;
    const std::vector<std::string> placed = placed_by_look(id);
    if (!placed.empty())
      note = "second look: " + std::to_string(placed.size()) +
             " names placed by their dots' look (" + first_and_more(placed) + ")";
    return true;
  }
  // The first look renames alone; a look after an unjudged one only as the one before it did
  // (a dim face's third look, as sure as the start, moved the lower lip's names onto their
  // neighbours' dots).
  if (!confirmed && !(as_sure && looks == 1)) return false;
  if (!enough(id.dots.size() + id.tags.size())) return true;
  // What each renamed dot was: the name the new naming gives the dot at its place, or none.
  corrections.clear();
  for (size_t i = 0; i < states.size(); ++i) {
    const std::string& from = states[i].spec->id;
    if (std::find(moved.begin(), moved.end(), from) == moved.end()) continue;
    const double width = std::max(reference_diameter[i], 2.0) * face_scale;
    std::string to;
    double nearest = width;
    for (const auto& [name, dot] : id.dots)
      if (const double d = cv::norm(dot.center - states[i].position); d < nearest)
        nearest = d, to = name;
    corrections.push_back({from, to});
  }
  corrected_since = started_at;
  begin(adopt(id));
  started_at = frame;
  note = "identified again (" + std::to_string(moved.size()) +
         " names moved: " + first_and_more(moved) + "), " + describe(identification);
  return true;
}

std::string MarkerTracker::Impl::first_and_more(const std::vector<std::string>& names) {
  return names.front() + (names.size() > 1 ? ", ..." : "");
}

std::vector<std::string> MarkerTracker::Impl::placed_by_look(const Identification& id) {
  std::vector<std::string> placed;
  for (size_t i = 0; i < states.size(); ++i) {
    MarkerState& s = states[i];
    const auto named = id.dots.find(s.spec->id);
    if (s.spec->is_tag() || named == id.dots.end()) continue;
    const double width = std::max(reference_diameter[i], 2.0);
    if (s.valid && cv::norm(named->second.center - s.position) <= width) continue;
    const std::optional<Dot> fresh = refine_dot(gray, named->second.center, 2, dot_options(i));
    if (!fresh) continue;
    if (s.valid) {
      // Only onto a blob that looks like its dot, as a lost dot is found again: where the
      // followed dot cannot be measured afresh (beside the dark lip), the lip's edge passed.
      if (!looks_like_itself(i, *fresh)) continue;
      const std::optional<Dot> followed = refine_dot(gray, s.position, 2, dot_options(i));
      if (followed && unlike_a_dot(*followed) <= unlike_a_dot(*fresh)) continue;
    }
    bool taken = false;
    for (size_t j = 0; j < states.size(); ++j)
      taken |= j != i && states[j].valid && !states[j].spec->is_tag() &&
               cv::norm(states[j].position - fresh->center) < width;
    if (taken) continue;
    found_on(i, *fresh);
    unconfirmed.insert(i);  // named by one frame's naming, as at the start
    placed.push_back(s.spec->id);
  }
  return placed;
}

void MarkerTracker::Impl::check_identities() {
  if (unconfirmed.empty()) return;
  std::vector<Dot> places;
  std::vector<size_t> owner;
  std::vector<TagDetection> tags;
  for (size_t i = 0; i < states.size(); ++i) {
    const MarkerState& s = states[i];
    if (!s.valid) continue;
    if (s.spec->is_tag()) {
      TagDetection t;
      t.family = s.spec->family, t.id = s.spec->tag_id;
      t.corners = s.corners, t.center = s.position;
      tags.push_back(t);
    } else {
      Dot d;
      d.center = s.position, d.diameter = reference_diameter[i];
      places.push_back(d), owner.push_back(i);
    }
  }
  if (tags.empty()) return;
  const Identification id =
      identify_markers(layout, places, tags, options.identification, face_places(tags));
  if (!id.confidence.confident || (face_prior.available() && !id.confidence.face_model)) return;
  // Each followed dot's name in the naming; a dot it leaves out is no evidence.
  std::map<std::string, std::string> called;
  for (size_t k = 0; k < places.size(); ++k)
    for (const auto& [name, dot] : id.dots)
      if (dot.center == places[k].center) called[states[owner[k]].spec->id] = name;
  auto index_of = [&](const std::string& name) {
    const MarkerSpec* spec = layout.find(name);
    return spec != nullptr ? static_cast<size_t>(spec - layout.markers.data()) : states.size();
  };
  // The calls that hold: decisive and the same as on the last check.
  std::map<size_t, size_t> calls;               // state index -> the index of its new name
  std::map<std::string, std::string> misnamed;  // this check's calls, for the next one
  for (const auto& [own, name] : called) {
    const size_t from = index_of(own), to = index_of(name);
    if (!unconfirmed.count(from)) continue;  // LK has followed it since a check confirmed it
    const auto own_place = id.places.find(own);
    if (own_place == id.places.end()) continue;
    const cv::Point2d at = states[from].position;
    // The place of the name nearest the dot but the one under test.
    auto nearest_but = [&](const std::string& skip) {
      double best = std::numeric_limits<double>::max();
      for (const auto& [other, place] : id.places)
        if (other != skip) best = std::min(best, cv::norm(at - place));
      return best;
    };
    if (name == own) {
      // Confirmed: decisively nearer its own place than any other name's.
      if (cv::norm(at - own_place->second) <= kDecisive * nearest_but(own)) unconfirmed.erase(from);
      continue;
    }
    if (to == states.size() || states[to].spec->is_tag()) continue;
    // Decisively nearer the other name's place than its own: where the two are about as
    // near (a blink brings the lids together, blur smears the eye) the naming guesses.
    const auto other_place = id.places.find(name);
    if (other_place == id.places.end()) continue;
    if (cv::norm(at - other_place->second) > kDecisive * cv::norm(at - own_place->second)) continue;
    misnamed[own] = name;
    // A face deforming beyond the arrangements the naming knows (a mouth wide open) fools
    // it for a moment; a wrong name stays. So the call must hold on two checks in a row.
    const auto before = called_otherwise.find(own);
    if (before != called_otherwise.end() && before->second == name) calls[from] = to;
  }
  called_otherwise = std::move(misnamed);
  rename(moving_together(calls));
}

std::vector<std::pair<size_t, size_t>> MarkerTracker::Impl::moving_together(
    const std::map<size_t, size_t>& calls) {
  std::set<size_t> moving;
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [from, to] : calls)
      if (!moving.count(from) && (!states[to].valid || moving.count(to)))
        moving.insert(from), grew = true;
  }
  for (const auto& [from, to] : calls) {
    if (moving.count(from)) continue;
    std::vector<size_t> ring{from};
    for (size_t at = to; at != from;) {
      const auto next = calls.find(at);
      if (next == calls.end() || moving.count(at) ||
          std::find(ring.begin(), ring.end(), at) != ring.end()) {
        ring.clear();
        break;
      }
      ring.push_back(at), at = next->second;
    }
    moving.insert(ring.begin(), ring.end());
  }
  std::vector<std::pair<size_t, size_t>> moves;
  for (size_t from : moving) moves.push_back({from, calls.at(from)});
  return moves;
}

void MarkerTracker::Impl::rename(const std::vector<std::pair<size_t, size_t>>& moves) {
  if (moves.empty()) return;
  const std::vector<MarkerState> before = states;
  for (const auto& [from, to] : moves) states[from].valid = false;
  note = "identities checked: renamed";
  for (const auto& [from, to] : moves) {
    MarkerState& s = states[to];
    s.valid = true, s.position = before[from].position, s.quality = before[from].quality;
    s.lost_reason = LostReason::None;
    note += " " + before[from].spec->id + " -> " + s.spec->id;
  }
  for (const auto& [from, to] : moves)
    if (!states[from].valid) states[from].lost_reason = LostReason::Identity;
}

std::map<std::string, cv::Point2d> MarkerTracker::Impl::face_places(
    const std::vector<TagDetection>& tags) {
  if (!face_prior.available()) return {};
  const auto to_image = layout_to_image(tags);
  if (!to_image) return {};
  std::map<std::string, cv::Point2d> placed;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) placed[m.id] = apply(*to_image, m.frontal());
  const auto box = face_prior.placed_box(layout, placed);
  if (!box) return {};
  // The model reads the face around its box; the grey image is converted where needed.
  const double pad = 0.25 * box->width;
  ensure_gray(cv::Rect(
      cv::Point(static_cast<int>(box->x - pad), static_cast<int>(box->y - pad)),
      cv::Point(static_cast<int>(box->br().x + pad) + 1, static_cast<int>(box->br().y + pad) + 1)));
  return face_prior.fitted(gray, layout, *box);
}

void MarkerTracker::Impl::swap_back_pairs(long frame) {
  std::map<std::pair<size_t, size_t>, Dot> calls;  // (a, b) -> the free dot a takes
  for (size_t a = 0; face_fit && a < states.size(); ++a) {
    if (!states[a].valid || states[a].spec->is_tag()) continue;
    std::vector<size_t> lost;  // a's lost neighbours, within two of their spacings
    for (size_t b = 0; b < states.size(); ++b)
      if (!states[b].valid && !states[b].spec->is_tag() &&
          cv::norm(reference[a] - reference[b]) <= 2 * spacing[b])
        lost.push_back(b);
    if (lost.empty()) continue;
    // a's place by every other marker: the face's fit, moved with the jaw for the jaw's dots.
    const cv::Point2d t = states[a].position,
                      own = apply(placed_by_jaw(a) ? moved_with_jaw(*face_fit, a) : *face_fit,
                                  reference[a]);
    // A free dot lies at least half a spacing from t, and it must lie nearer `own` than t
    // does: t a quarter spacing or more from there.
    if (cv::norm(t - own) < 0.25 * spacing[a] * face_scale) continue;
    const double radius = options.search_fraction * spacing[a] * face_scale;
    ensure_gray_around(own, radius);
    const double least = options.min_contrast_ratio * reference_contrast[a];
    std::vector<Dot> free;  // nearest `own` first
    for (const Dot& d : dots_near(gray, own, radius, dot_options(a), 4, least))
      if (cv::norm(d.center - own) <= radius && !followed_dot_at(d.center, face_scale) &&
          cv::norm(d.center - own) < cv::norm(t - own) && dot_passes(a, d, false))
        free.push_back(d);
    for (size_t b : lost) {
      // From a's place to b's, as the face's fit maps the layout now.
      const cv::Point2d v = apply_linear(*face_fit, reference[b] - reference[a]);
      // b on t and a on d, against a on t and b on d: the pair's offset either way round.
      const auto decides = [&](const Dot& d) {
        return cv::norm(t - d.center - v) <= kDecisive * cv::norm(d.center - t - v);
      };
      const auto d = std::find_if(free.begin(), free.end(), decides);
      if (d != free.end()) calls.emplace(std::make_pair(a, b), *d);
    }
  }
  std::set<size_t> done;
  std::string swapped;  // "a <-> b, ..." for the frame's note
  for (const auto& [pair, d] : calls) {
    const auto [a, b] = pair;
    if (!pair_calls_before.count(pair) || done.count(a) || done.count(b)) continue;
    done.insert(a), done.insert(b);
    MarkerState& lost = states[b];
    lost.valid = true, lost.position = states[a].position, lost.quality = states[a].quality;
    lost.lost_reason = LostReason::None;
    recent_diameter[b] = recent_diameter[a], last_diameter[b] = last_diameter[a];
    recent_elongation[b] = recent_elongation[a];
    found_on(a, d);
    unconfirmed.insert(a), unconfirmed.insert(b);  // as any dot found again
    // Since b was lost, the dot followed as a was b's: the frames given out since then are
    // corrected (and a's own dot is unknown there). A take written as it goes holds only the
    // last kSwapBackReach of them; one held whole takes them all.
    const long since = frame - lost.lost_frames;
    corrections.push_back({states[a].spec->id, lost.spec->id, since});
    corrected_since = corrections.size() == 1 ? since : std::min(corrected_since, since);
    swapped += (swapped.empty() ? "" : ", ") + states[a].spec->id + " <-> " + lost.spec->id;
  }
  if (!swapped.empty())
    note += (note.empty() ? "" : "; ") + std::string("identities swapped back: ") + swapped;
  pair_calls_before.clear();
  for (const auto& [pair, d] : calls) pair_calls_before.insert(pair);
}

}  // namespace rostro::tracking
