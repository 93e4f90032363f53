-- A receptionist waiting for visitors (seed004 7.1): a polite half smile, calm blinks, idle
-- glances and small head tilts, computed by a loop. math.random follows --seed, so every seed
-- gives another idle minute, the same on every run.
--   rostro script data/scripts/receptionist.lua -o idle.fap --seed 3
local seconds = 60
local eyes = { { "blinks", rate = 14 }, { "saccades", "listening" } }
local head = {}

local t = 1.0
while t < seconds - 4 do
  local r = math.random()
  if r < 0.4 then  -- a glance aside
    local side = math.random() < 0.5 and "left" or "right"
    eyes[#eyes + 1] = { "look", side, at = t, duration = 1 + 2 * math.random(),
                        amplitude = 10 + 15 * math.random() }
  elseif r < 0.6 then  -- a look at the desk
    eyes[#eyes + 1] = { "look", "down", at = t, duration = 1.5, amplitude = 12 }
  elseif r < 0.8 then
    local side = math.random() < 0.5 and "left" or "right"
    head[#head + 1] = { "tilt", side, at = t, duration = 2, amplitude = 3 }
  end
  t = t + 4 + 3 * math.random()
end

storyboard = {
  duration = seconds,
  expressions = { { "joy", at = 0, intensity = 0.25 } },  -- held to the end
  eyes = eyes,
  head = head,
}
