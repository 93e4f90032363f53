#include "script/storyboard_reader.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <lua.hpp>
#include <numbers>
#include <sstream>

#include "facecore/error.hpp"
#include "facecore/expression_library.hpp"
#include "script/lua_table.hpp"
#include "speech/emotion_markup.hpp"

namespace rostro::script {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::string seconds(double s) {
  return fmt::format("{:g} s", s);
}

// Where the next entry of a sequence starts when it gives no `at`, and the check that time
// never runs backwards.
struct Cursor {
  bool any = false;
  double previous_at = 0.0;
  double next = 0.0;
};

struct Timing {
  double at = 0.0;
  double end = kOpenEnd;
};

// `at`, `duration` (or the positional one) and `to`; `fixed_s` >= 0 is the entry's own
// length when it has no duration (a blink), < 0 leaves it open-ended.
Timing read_timing(const LuaTable& t, Cursor& cursor, std::optional<double> positional,
                   double fixed_s = -1.0) {
  const auto at = t.number("at");
  if (at && *at < 0) t.fail(fmt::format("at = {}: a time cannot be negative", seconds(*at)));
  Timing out;
  out.at = at ? *at : cursor.next;
  if (cursor.any && out.at < cursor.previous_at)
    t.fail(fmt::format("time runs backwards: at = {} is before the previous entry's {}",
                       seconds(out.at), seconds(cursor.previous_at)));
  auto duration = t.number("duration");
  if (duration && positional) t.fail("the duration is given twice (entry 2 and duration =)");
  if (!duration) duration = positional;
  const auto to = t.number("to");
  if (duration && to) t.fail("give duration or to, not both");
  if (duration && *duration < 0)
    t.fail(fmt::format("negative duration ({}): a duration is 0 or more", seconds(*duration)));
  if (to && *to < out.at)
    t.fail(fmt::format("time runs backwards: it ends (to = {}) before it starts (at = {})",
                       seconds(*to), seconds(out.at)));
  if (duration)
    out.end = out.at + *duration;
  else if (to)
    out.end = *to;
  else if (fixed_s >= 0)
    out.end = out.at + fixed_s;
  cursor.any = true;
  cursor.previous_at = out.at;
  cursor.next = std::isfinite(out.end) ? out.end : out.at;
  return out;
}

template <typename Item>
void set_timing(Item& item, const Timing& timing) {
  item.at = timing.at;
  item.end = timing.end;
}

double read_ramp(const LuaTable& t, const char* name, double fallback) {
  const auto v = t.number(name);
  if (v && *v < 0) t.fail(fmt::format("{} = {}: a ramp is 0 or more", name, seconds(*v)));
  return v ? *v : fallback;
}

double read_unit(const LuaTable& t, const char* name, double fallback) {
  const auto v = t.number(name);
  if (v && (*v < 0 || *v > 1)) t.fail(fmt::format("{} = {:g}: should be in 0..1", name, *v));
  return v ? *v : fallback;
}

// The direction at the top of the stack: a name or a table (yaw/pitch/roll or x/y/z).
Direction read_direction(const LuaTable& owner, const std::string& what, double sideways,
                         double vertical) {
  lua_State* L = owner.state();
  if (lua_type(L, -1) == LUA_TSTRING) {
    const std::string name = lua_tostring(L, -1);
    const auto d = named_direction(name, sideways, vertical);
    if (!d)
      owner.fail(
          fmt::format("{}: unknown direction '{}' (expected camera, left, right, up, down, "
                      "a pair such as up_left, {{yaw=, pitch=}} or {{x=, y=, z=}})",
                      what, name));
    return *d;
  }
  const LuaTable t(L, -1, owner.origin() + ": " + what);
  t.allow({"yaw", "pitch", "roll", "x", "y", "z"}, 0);
  Direction d;
  if (t.has("x") || t.has("y") || t.has("z")) {
    const double x = t.number("x").value_or(0), y = t.number("y").value_or(0),
                 z = t.number("z").value_or(1);
    if (z <= 0) t.fail("z should be > 0: the point must be in front of the face");
    d.yaw_deg = std::atan2(x, z) * kDegPerRad;
    d.pitch_deg = std::atan2(-y, std::hypot(x, z)) * kDegPerRad;
  } else {
    d.yaw_deg = t.number("yaw").value_or(0);
    d.pitch_deg = t.number("pitch").value_or(0);
    d.roll_deg = t.number("roll").value_or(0);
  }
  for (double a : {d.yaw_deg, d.pitch_deg, d.roll_deg})
    if (std::abs(a) > 60) t.fail("angles beyond 60 degrees are out of a face's reach");
  return d;
}

class Reader {
 public:
  Reader(LuaSandbox& sandbox, Storyboard& board) : sandbox_(sandbox), board_(board) {}

  void read(const LuaTable& top);

 private:
  // Calls `entry(table)` for each element of the part `name`, given inline or as a file.
  template <typename Fn>
  void each(const LuaTable& top, const char* name, Fn entry);
  std::filesystem::path file(const std::string& name, const std::string& origin) {
    return sandbox_.inside(name, origin);
  }

  void speech_item(const LuaTable& t);
  void visemes(const LuaTable& t, SpeechItem& item);
  void expression(const LuaTable& t, Cursor& c);
  void eye(const LuaTable& t, Cursor& c);
  void head(const LuaTable& t, Cursor& c);

  LuaSandbox& sandbox_;
  Storyboard& board_;
};

template <typename Fn>
void Reader::each(const LuaTable& top, const char* name, Fn entry) {
  lua_State* L = top.state();
  const int type = top.push(name);
  std::string where = top.origin() + ": " + name;
  if (type == LUA_TNIL || (type == LUA_TSTRING && std::string(lua_tostring(L, -1)) == "none")) {
    lua_pop(L, 1);
    return;
  }
  if (type == LUA_TSTRING) {
    const std::string file_name = lua_tostring(L, -1);
    lua_pop(L, 1);
    sandbox_.load_sequence(file_name, where);
    where = sandbox_.display(sandbox_.inside(file_name, where));
  } else if (type != LUA_TTABLE) {
    lua_pop(L, 1);
    top.fail(std::string(name) + " should be a table, a sequence file name or \"none\"");
  }
  const LuaTable list(L, -1, where);
  list.allow({}, static_cast<int>(list.length()));
  for (long long i = 1; i <= list.length(); ++i) {
    list.push(static_cast<int>(i));
    entry(LuaTable(L, -1, fmt::format("{}[{}]", where, i)));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

void Reader::read(const LuaTable& top) {
  top.allow({"fps", "seed", "duration", "output", "speech", "expressions", "eyes", "head"}, 0);
  if (const auto fps = top.number("fps")) {
    if (!(*fps > 0 && *fps <= 1000))
      top.fail(fmt::format("fps = {:g}: should be in (0, 1000]", *fps));
    board_.fps = *fps;
    board_.fps_set = true;
  }
  if (const auto seed = top.number("seed")) {
    if (*seed < 0 || *seed != std::floor(*seed)) top.fail("seed should be a whole number >= 0");
    board_.seed = static_cast<std::uint64_t>(*seed);
    board_.seed_set = true;
  }
  if (const auto d = top.number("duration")) {
    if (*d < 0) top.fail(fmt::format("negative duration ({})", seconds(*d)));
    board_.duration = *d;
  }
  if (const auto out = top.string("output")) board_.output = file(*out, top.origin() + ": output");

  // speech: one item (a table with text, sound, pho or visemes) or a list of them.
  lua_State* L = top.state();
  if (top.push("speech") == LUA_TTABLE) {
    const LuaTable s(L, -1, top.origin() + ": speech");
    const bool single =
        s.has("text") || s.has("text_file") || s.has("sound") || s.has("pho") || s.has("visemes");
    lua_pop(L, 1);
    if (single) {
      top.push("speech");
      speech_item(LuaTable(L, -1, top.origin() + ": speech"));
      lua_pop(L, 1);
    } else {
      each(top, "speech", [&](const LuaTable& t) { speech_item(t); });
    }
  } else {
    lua_pop(L, 1);
    each(top, "speech", [&](const LuaTable& t) { speech_item(t); });
  }
  Cursor ce, cy, ch;
  each(top, "expressions", [&](const LuaTable& t) { expression(t, ce); });
  each(top, "eyes", [&](const LuaTable& t) { eye(t, cy); });
  each(top, "head", [&](const LuaTable& t) { head(t, ch); });
}

void Reader::speech_item(const LuaTable& t) {
  t.allow({"text", "text_file", "lang", "voice", "rate", "sound", "pho", "at", "visemes",
           "duration", "emotions", "emotion"},
          1);
  SpeechItem item;
  item.origin = t.origin();
  const auto at = t.number("at");
  if (at && *at < 0) t.fail(fmt::format("at = {}: a time cannot be negative", seconds(*at)));
  item.at = at.value_or(board_.speech.empty() ? 0.0 : -1.0);  // -1: after the previous one
  if (!board_.speech.empty() && at && *at < board_.speech.back().at)
    t.fail(fmt::format("time runs backwards: at = {} is before the previous speech's {}",
                       seconds(*at), seconds(board_.speech.back().at)));
  if (auto text = t.string(1)) item.text = *text;
  if (auto text = t.string("text")) {
    if (!item.text.empty()) t.fail("the text is given twice (entry 1 and text =)");
    item.text = *text;
  }
  if (auto name = t.string("text_file")) {
    if (!item.text.empty()) t.fail("give text or text_file, not both");
    std::ifstream in(file(*name, t.origin()));
    if (!in) t.fail("cannot read the text file '" + *name + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    item.text = ss.str();
  }
  if (auto lang = t.string("lang")) item.language = *lang;
  if (auto voice = t.string("voice")) item.voice = *voice;
  if (auto rate = t.number("rate")) {
    if (*rate < 80 || *rate > 450) t.fail("rate should be 80..450 words per minute");
    item.rate_wpm = static_cast<int>(*rate);
  }
  if (auto sound = t.string("sound")) item.sound = file(*sound, t.origin());
  if (auto pho = t.string("pho")) item.pho = file(*pho, t.origin());
  if (const auto d = t.number("duration")) {
    if (*d < 0) t.fail(fmt::format("negative duration ({})", seconds(*d)));
    item.duration = *d;
  }
  if (t.has("visemes")) visemes(t, item);
  const int sources = !item.text.empty() + !item.pho.empty() + item.has_visemes;
  if (sources > 1) t.fail("give one of text, pho or visemes");
  // A sound alone is English speech recognised without a transcript (rostro speak --audio).
  if (sources == 0 && item.sound.empty())
    t.fail("nothing to say: give text, text_file, sound, pho or visemes");
  if (item.duration >= 0 && !item.has_visemes) t.fail("duration goes with visemes");
  board_.speech.push_back(std::move(item));
}

void Reader::visemes(const LuaTable& t, SpeechItem& item) {
  lua_State* L = t.state();
  item.has_visemes = true;
  t.push("visemes");
  const LuaTable list(L, -1, t.origin() + ": visemes");
  double previous_end = 0.0;
  for (long long i = 1; i <= list.length(); ++i) {
    list.push(static_cast<int>(i));
    const LuaTable v(L, -1, fmt::format("{}[{}]", list.origin(), i));
    v.allow({"word", "phoneme", "closes"}, 4);
    speech::Phoneme p;
    p.start_s = v.number(1).value_or(-1);
    p.end_s = v.number(2).value_or(-1);
    if (p.start_s < 0 || p.end_s < p.start_s)
      v.fail("should start {start, end, viseme, class} with 0 <= start <= end");
    if (p.start_s < previous_end - 1e-9)
      v.fail(fmt::format("time runs backwards: starts at {} before the previous viseme ends ({})",
                         seconds(p.start_s), seconds(previous_end)));
    previous_end = p.end_s;
    const std::string name = v.string(3).value_or("");
    p.viseme = -1;
    for (int k = 0; k < kVisemeCount; ++k)
      if (ExpressionLibrary::viseme_name(k) == name) p.viseme = k;
    if (p.viseme < 0) v.fail("unknown viseme '" + name + "'");
    const std::string cls = v.string(4).value_or(p.viseme == 0 ? "silence" : "");
    if (cls == "vowel")
      p.cls = speech::PhonemeClass::Vowel;
    else if (cls == "consonant")
      p.cls = speech::PhonemeClass::Consonant;
    else if (cls == "silence")
      p.cls = speech::PhonemeClass::Silence;
    else
      v.fail("class '" + cls + "' should be vowel, consonant or silence");
    p.word = static_cast<int>(v.number("word").value_or(-1));
    p.symbol = v.string("phoneme").value_or(name);
    p.closes_lips = v.boolean("closes").value_or(false);
    item.visemes.push_back(std::move(p));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  if (item.visemes.empty()) t.fail("visemes is empty");

  if (t.push("emotion") != LUA_TNIL) {
    const LuaTable e(L, -1, t.origin() + ": emotion");
    e.allow({}, 2);
    item.base_expression = speech::emotion_from_name(e.string(1).value_or(""));
    if (item.base_expression < 0)
      e.fail("unknown expression (expected " + speech::known_emotion_names() + ")");
    item.base_intensity = read_unit(e, "intensity", e.number(2).value_or(1.0));
  }
  lua_pop(L, 1);
  if (t.push("emotions") != LUA_TNIL) {
    const LuaTable list_e(L, -1, t.origin() + ": emotions");
    for (long long i = 1; i <= list_e.length(); ++i) {
      list_e.push(static_cast<int>(i));
      const LuaTable e(L, -1, fmt::format("{}[{}]", list_e.origin(), i));
      e.allow({}, 4);
      speech::EmotionEvent ev;
      ev.time_s = e.number(1).value_or(-1);
      if (ev.time_s < 0) e.fail("should be {time, expression, intensity, ramp}");
      ev.expression = speech::emotion_from_name(e.string(2).value_or(""));
      if (ev.expression < 0)
        e.fail("unknown expression (expected " + speech::known_emotion_names() + ")");
      ev.intensity = e.number(3).value_or(1.0);
      ev.ramp_s = e.number(4).value_or(0.3);
      if (ev.intensity < 0 || ev.intensity > 1 || ev.ramp_s < 0)
        e.fail("intensity should be in 0..1 and the ramp 0 or more");
      item.emotions.push_back(ev);
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
}

void Reader::expression(const LuaTable& t, Cursor& c) {
  t.allow({"at", "duration", "to", "intensity", "ramp", "ramp_in", "ramp_out", "ease"}, 3);
  ExpressionItem e;
  e.origin = t.origin();
  const std::string name = t.string(1).value_or("");
  e.expression = speech::emotion_from_name(name);
  if (e.expression < 0)
    t.fail("unknown expression '" + name + "' (expected " + speech::known_emotion_names() + ")");
  if (t.number(3) && t.has("intensity")) t.fail("the intensity is given twice");
  e.intensity = read_unit(t, "intensity", t.number(3).value_or(1.0));
  set_timing(e, read_timing(t, c, t.number(2)));
  const double ramp = read_ramp(t, "ramp", 0.3);
  e.ramp_in = read_ramp(t, "ramp_in", ramp);
  e.ramp_out = std::isfinite(e.end) ? read_ramp(t, "ramp_out", ramp) : 0.0;
  const double length = e.end - e.at;
  if (e.ramp_in + e.ramp_out > length) {  // a short expression: ramps share its length
    const double scale = length / (e.ramp_in + e.ramp_out);
    e.ramp_in *= scale;
    e.ramp_out *= scale;
  }
  const std::string ease = t.string("ease").value_or("linear");
  if (ease == "smooth")
    e.ease = Ease::Smooth;
  else if (ease != "linear")
    t.fail("ease = '" + ease + "' (expected linear or smooth)");
  board_.expressions.push_back(e);
}

void Reader::eye(const LuaTable& t, Cursor& c) {
  const std::string kind = t.string(1).value_or("");
  EyeAction a;
  a.origin = t.origin();
  lua_State* L = t.state();
  if (kind == "look") {
    t.allow({"at", "duration", "to", "target", "amplitude"}, 2);
    const double amplitude = t.number("amplitude").value_or(-1);
    if (t.push(2) == LUA_TNIL) {
      lua_pop(L, 1);
      t.push("target");
    }
    if (lua_isnil(L, -1)) t.fail("look needs a target: {\"look\", \"left\", at = 1}");
    a.path.push_back(read_direction(t, "target", amplitude >= 0 ? amplitude : 20,
                                    amplitude >= 0 ? amplitude : 15));
    lua_pop(L, 1);
    a.kind = EyeKind::Look;
    set_timing(a, read_timing(t, c, std::nullopt));
  } else if (kind == "pursuit") {
    t.allow({"at", "duration", "to", "path"}, 1);
    a.kind = EyeKind::Pursuit;
    if (t.push("path") != LUA_TTABLE) t.fail("pursuit needs path = {target, target, ...}");
    const LuaTable path(L, -1, t.origin() + ": path");
    for (long long i = 1; i <= path.length(); ++i) {
      path.push(static_cast<int>(i));
      a.path.push_back(read_direction(path, fmt::format("path[{}]", i), 20, 15));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    if (a.path.size() < 2) t.fail("pursuit needs at least two points in path");
    set_timing(a, read_timing(t, c, std::nullopt));
    if (!std::isfinite(a.end) || a.end <= a.at) t.fail("pursuit needs a duration > 0");
  } else if (kind == "blink") {
    t.allow({"at"}, 1);
    a.kind = EyeKind::Blink;
    a.at = read_timing(t, c, std::nullopt, 0.28).at;
    a.end = a.at + 0.28;
  } else if (kind == "blinks") {
    t.allow({"at", "duration", "to", "rate"}, 1);
    a.kind = EyeKind::Blinks;
    const auto rate = t.number("rate");
    if (rate && !(*rate > 0 && *rate <= 60)) t.fail("rate should be in (0, 60] blinks a minute");
    a.rate_per_min = rate.value_or(0);
    set_timing(a, read_timing(t, c, std::nullopt));
  } else if (kind == "saccades") {
    t.allow({"at", "duration", "to", "style"}, 2);
    a.kind = EyeKind::Saccades;
    a.style = t.string(2).value_or(t.string("style").value_or("talking"));
    if (a.style != "talking" && a.style != "listening" && a.style != "thinking")
      t.fail("unknown saccade style '" + a.style + "' (expected talking, listening, thinking)");
    set_timing(a, read_timing(t, c, std::nullopt));
  } else if (kind == "close" || kind == "half_close") {
    t.allow({"at", "duration", "to", "amount", "ramp"}, 2);
    a.kind = EyeKind::Close;
    a.amount = read_unit(t, "amount", kind == "close" ? 1.0 : 0.5);
    a.ramp = read_ramp(t, "ramp", 0.1);
    set_timing(a, read_timing(t, c, t.number(2)));
  } else {
    t.fail("unknown eye behaviour '" + kind +
           "' (expected look, pursuit, blink, blinks, saccades, close, half_close)");
  }
  board_.eyes.push_back(std::move(a));
}

void Reader::head(const LuaTable& t, Cursor& c) {
  const std::string kind = t.string(1).value_or("");
  HeadAction h;
  h.origin = t.origin();
  t.allow({"at", "duration", "to", "amplitude", "count", "target", "ramp"}, 2);
  const auto amplitude = t.number("amplitude");
  if (amplitude && (*amplitude < 0 || *amplitude > 45))
    t.fail(fmt::format("amplitude = {:g}: should be 0..45 degrees", *amplitude));
  const auto count = t.number("count");
  if (count && (*count < 1 || *count > 20 || *count != std::floor(*count)))
    t.fail("count should be a whole number 1..20");
  h.count = static_cast<int>(count.value_or(1));
  h.ramp = read_ramp(t, "ramp", 0.4);
  double default_s = -1;
  if (kind == "nod") {
    h.kind = HeadKind::Nod;
    h.amplitude_deg = amplitude.value_or(6);
    default_s = 0.6 * h.count;
  } else if (kind == "shake") {
    h.kind = HeadKind::Shake;
    h.count = static_cast<int>(count.value_or(2));
    h.amplitude_deg = amplitude.value_or(8);
    default_s = 0.5 * h.count;
  } else if (kind == "tilt") {
    h.kind = HeadKind::Tilt;
    h.amplitude_deg = amplitude.value_or(8);
    const std::string side = t.string(2).value_or(t.string("target").value_or("right"));
    if (side != "left" && side != "right") t.fail("tilt goes left or right, not '" + side + "'");
    h.target.roll_deg = side == "right" ? h.amplitude_deg : -h.amplitude_deg;
    default_s = 1.5;
  } else if (kind == "turn") {
    h.kind = HeadKind::Turn;
    if (t.push(2) == LUA_TNIL) {
      lua_pop(t.state(), 1);
      t.push("target");
    }
    if (lua_isnil(t.state(), -1)) t.fail("turn needs a target: {\"turn\", \"left\", at = 1}");
    h.target = read_direction(t, "target", amplitude.value_or(20), amplitude.value_or(12));
    lua_pop(t.state(), 1);
  } else if (kind == "still") {
    h.kind = HeadKind::Still;
  } else {
    t.fail("unknown head action '" + kind + "' (expected nod, shake, tilt, turn, still)");
  }
  set_timing(h, read_timing(t, c, std::nullopt, default_s));
  if ((h.kind == HeadKind::Nod || h.kind == HeadKind::Shake || h.kind == HeadKind::Tilt) &&
      !(h.end > h.at))
    t.fail(kind + " needs a duration > 0");
  board_.head.push_back(h);
}

}  // namespace

std::optional<Direction> named_direction(const std::string& name, double sideways_deg,
                                         double vertical_deg) {
  Direction d;
  std::string word;
  std::istringstream in(name);
  bool any = false;
  for (std::string token; std::getline(in, token, '_');) {
    if (token == "camera" || token == "ahead")
      ;
    else if (token == "left")
      d.yaw_deg += sideways_deg;
    else if (token == "right")
      d.yaw_deg -= sideways_deg;
    else if (token == "up")
      d.pitch_deg -= vertical_deg;
    else if (token == "down")
      d.pitch_deg += vertical_deg;
    else
      return std::nullopt;
    any = true;
  }
  if (!any) return std::nullopt;
  return d;
}

Storyboard read_storyboard(const std::filesystem::path& file, std::uint64_t seed,
                           const SandboxOptions& options) {
  Storyboard board;
  board.file = file;
  board.folder = file.parent_path();
  board.seed = seed;
  LuaSandbox sandbox(board.folder.empty() ? "." : board.folder, seed, options);
  sandbox.run_file(file);
  lua_State* L = sandbox.state();
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    lua_getglobal(L, "storyboard");
  }
  if (!lua_istable(L, -1))
    throw InputError(file.string() +
                     ": sets no storyboard (storyboard = { speech = ..., expressions = ... })");
  Reader(sandbox, board).read(LuaTable(L, -1, file.string()));
  lua_pop(L, 1);
  return board;
}

}  // namespace rostro::script
