-- A reaction without speech: something moves at the character's left; a surprised double
-- take, a moment of fear, then relief while the eyes follow it across.
--   rostro script data/scripts/reaction.lua -o reaction.fap
storyboard = {
  duration = 5.5,
  expressions = {
    { "surprise", at = 1.0, duration = 1.2, ramp = 0.15 },
    { "fear", at = 2.0, duration = 0.8, intensity = 0.4 },
    { "joy", at = 3.0, to = 5.5, intensity = 0.7, ease = "smooth" },
  },
  eyes = {
    { "blinks" },
    { "look", "left", at = 0.9, duration = 0.5, amplitude = 30 },
    { "blink", at = 1.6 },
    { "look", "left", at = 1.9, duration = 1.0, amplitude = 30 },
    { "pursuit", at = 3.0, duration = 1.5, path = { "left", { yaw = 0, pitch = -5 }, "right" } },
  },
  head = {
    { "turn", { yaw = 10 }, at = 1.9, duration = 1.0, ramp = 0.25 },
    { "shake", at = 4.6, amplitude = 4 },
  },
}
