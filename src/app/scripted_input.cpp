// Parsing `run --input` events into GLFW's key codes and modifiers.
#include "app/scripted_input.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <optional>
#include <cmath>
#include <string_view>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "core/text_escape.h"

namespace dentsim::app {
namespace {

struct NamedKey {
  std::string_view name;
  int key;
};

constexpr std::array<NamedKey, 11> kNamedKeys{{{"Space", GLFW_KEY_SPACE},
                                                {"PageUp", GLFW_KEY_PAGE_UP},
                                                {"PageDown", GLFW_KEY_PAGE_DOWN},
                                                {"Up", GLFW_KEY_UP},
                                                {"Down", GLFW_KEY_DOWN},
                                                {"Left", GLFW_KEY_LEFT},
                                                {"Right", GLFW_KEY_RIGHT},
                                                {"Escape", GLFW_KEY_ESCAPE},
                                                {"F1", GLFW_KEY_F1},
                                                {"Enter", GLFW_KEY_ENTER},
                                                {"Tab", GLFW_KEY_TAB}}};

std::optional<int> keyCode(std::string_view name) {
  if (name.size() == 1) {
    const char c = name[0];
    if (c >= 'A' && c <= 'Z') return GLFW_KEY_A + (c - 'A');
    if (c >= 'a' && c <= 'z') return GLFW_KEY_A + (c - 'a');
    if (c >= '0' && c <= '9') return GLFW_KEY_0 + (c - '0');
  }
  for (const NamedKey& k : kNamedKeys)
    if (k.name == name) return k.key;
  return std::nullopt;
}

std::optional<double> number(std::string_view s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Strips "shift+", "ctrl+" and "alt+" off the front of `s`, into GLFW modifier bits.
int takeModifiers(std::string_view& s) {
  int mods = 0;
  for (bool more = true; more;) {
    more = false;
    for (const auto& [prefix, bit] : {std::pair<std::string_view, int>{"shift+", GLFW_MOD_SHIFT},
                                      {"ctrl+", GLFW_MOD_CONTROL},
                                      {"alt+", GLFW_MOD_ALT}}) {
      if (s.substr(0, prefix.size()) == prefix) {
        mods |= bit;
        s.remove_prefix(prefix.size());
        more = true;
      }
    }
  }
  return mods;
}

}  // namespace

Result<ScriptedInput> parseScriptedInput(double t_s, const std::string& text) {
  // Escaped: a control byte in an argument cannot break the one line or reach the terminal.
  auto bad = [&](const std::string& why) { return Error{"--input \"" + escapeControl(text) + "\": " + why}; };
  if (!std::isfinite(t_s) || t_s < 0.0) return bad("the time must be a number of seconds >= 0");
  ScriptedInput in;
  in.t_s = t_s;
  in.text = text;
  std::string_view s = text;
  in.mods = takeModifiers(s);
  const size_t colon = s.find(':');
  if (colon == std::string_view::npos) return bad("expected key:NAME, wheel:STEPS, drag:DX,DY or click:WIDGET");
  const std::string_view verb = s.substr(0, colon), arg = s.substr(colon + 1);
  if (verb == "key") {
    const auto code = keyCode(arg);
    if (!code) return bad("no key named \"" + escapeControl(arg) + "\" (A-Z, 0-9, Space, PageUp, PageDown, Up, Down, Left, Right, Escape, F1, Enter, Tab)");
    in.kind = ScriptedInput::Kind::Key;
    in.key = *code;
  } else if (verb == "wheel") {
    const auto steps = number(arg);
    if (!steps || std::abs(*steps) > 100.0) return bad("the wheel's steps must be a number from -100 to 100");
    in.kind = ScriptedInput::Kind::Wheel;
    in.dy = *steps;
  } else if (verb == "drag") {
    const size_t comma = arg.find(',');
    const auto dx = comma == std::string_view::npos ? std::nullopt : number(arg.substr(0, comma));
    const auto dy = comma == std::string_view::npos ? std::nullopt : number(arg.substr(comma + 1));
    if (!dx || !dy || std::abs(*dx) > 10000.0 || std::abs(*dy) > 10000.0)
      return bad("a drag is DX,DY in pixels, each from -10000 to 10000");
    in.kind = ScriptedInput::Kind::Drag;
    in.dx = *dx;
    in.dy = *dy;
  } else if (verb == "click") {
    if (arg.empty() || arg.size() > 200) return bad("a click names a panel widget's key");
    if (in.mods != 0) return bad("a click takes no modifier");
    in.kind = ScriptedInput::Kind::Click;
    in.widget = std::string(arg);
  } else {
    return bad("unknown event \"" + escapeControl(verb) + "\" (key, wheel, drag or click)");
  }
  return in;
}

Result<std::vector<ScriptedInput>> parseScriptedInputs(const std::vector<std::pair<double, std::string>>& given) {
  std::vector<ScriptedInput> out;
  out.reserve(given.size());
  for (const auto& [t, text] : given) {
    auto in = parseScriptedInput(t, text);
    if (!in) return in.error();
    out.push_back(std::move(*in));
  }
  std::stable_sort(out.begin(), out.end(), [](const ScriptedInput& a, const ScriptedInput& b) { return a.t_s < b.t_s; });
  return out;
}

}  // namespace dentsim::app
