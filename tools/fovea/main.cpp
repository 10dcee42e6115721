// fovea: thin front end over the FoveaRT libraries.
#include <toolkit/run_cli.hpp>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fovea - FoveaRT foveation tool: point sets, interpolation, reconstruction, rendering, price list"};
  app.require_subcommand(1);
  foveart::fovea::register_pointset(app);
  register_interpolate(app);
  register_reconstruct(app);
  register_render(app);
  register_pricelist(app);
  return foveart::toolkit::run_cli(app, argc, argv, "fovea");
}
