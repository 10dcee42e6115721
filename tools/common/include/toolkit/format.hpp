// Numbers in the text the tools print (messages, ids, report cells) as a person
// would type them: printf's %g (0.5, 1, 200), not std::to_string's 200.000000.
#pragma once

#include <cstdio>
#include <string>

namespace foveart::toolkit {

inline std::string format_g(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

}  // namespace foveart::toolkit
