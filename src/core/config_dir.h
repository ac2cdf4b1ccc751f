// dentsim's folder in the user's configuration: where the presets and the controls overlay's "seen" mark live.
#pragma once

#include <cstdlib>
#include <string>

namespace dentsim {

// $XDG_CONFIG_HOME/dentsim when that is an absolute path (XDG says a relative one is invalid and
// must be ignored), else $HOME/.config/dentsim; empty when neither is set.
inline std::string userConfigDir() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  if (xdg && xdg[0] == '/') return std::string(xdg) + "/dentsim";
  const char* home = std::getenv("HOME");
  if (home && home[0] != '\0') return std::string(home) + "/.config/dentsim";
  return "";
}

}  // namespace dentsim
