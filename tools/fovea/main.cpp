// fovea: thin front end over the FoveaRT libraries.
#include <cstdio>
#include <exception>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fovea - FoveaRT foveation tool: point sets, interpolation, reconstruction, rendering, price list"};
  app.require_subcommand(1);
  foveart::fovea::register_pointset(app);
  register_interpolate(app);
  register_reconstruct(app);
  register_render(app);
  register_pricelist(app);
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
