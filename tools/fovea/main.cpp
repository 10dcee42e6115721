// fovea: thin front end over the FoveaRT libraries.
#include <cstdio>
#include <exception>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fovea - FoveaRT foveation tool: point sets, interpolation, reconstruction, rendering"};
  app.require_subcommand(1);
  foveart::fovea::register_pointset(app);
#ifdef FOVEA_HAS_INTERPOLATE
  register_interpolate(app);
  register_reconstruct(app);
#endif
#ifdef FOVEA_HAS_RENDER
  register_render(app);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    const auto subs = app.get_subcommands();
    std::fprintf(stderr, "fovea %s: error: %s\n", subs.empty() ? "" : subs.front()->get_name().c_str(), e.what());
    return 1;
  }
  return 0;
}
