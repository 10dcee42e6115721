// fovea: thin front end over the FoveaRT libraries.
#include <toolkit/run_cli.hpp>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fovea - FoveaRT foveation tool: point sets, interpolation, reconstruction, rendering"};
  app.require_subcommand(1);
  foveart::fovea::register_pointset(app);
  foveart::fovea::register_interpolate(app);
  foveart::fovea::register_reconstruct(app);
  foveart::fovea::register_render(app);
  return foveart::toolkit::run_cli(app, argc, argv, "fovea");
}
