-- A greeting: Spanish speech with a smile that grows, a nod and a friendly tilt.
--   rostro script data/scripts/greeting.lua -o greeting.fap --wav greeting.wav
storyboard = {
  speech = {
    text = "¡Hola! Bienvenidos. Me alegra mucho veros por aquí.",
    lang = "es",
    at = 0.3,
  },
  expressions = {
    { "joy", at = 0.0, duration = 1.6, intensity = 0.6, ramp = 0.4 },
    { "joy", at = 1.8, to = 4.2, intensity = 0.9, ease = "smooth" },
  },
  eyes = {
    { "blinks" },
    { "saccades", "talking" },
  },
  head = {
    { "nod", at = 0.5, amplitude = 5 },
    { "tilt", "right", at = 2.4, duration = 1.4, amplitude = 4 },
  },
}
