// fovea: thin front end over the FoveaRT libraries. The product's commands;
// the evaluation lab's are fovea-eval's.
#include <toolkit/run_cli.hpp>

#include "commands.hpp"

namespace {

// A command that moved to the lab: hidden from --help, and running it is an
// error saying where it is now instead of "a subcommand is required".
void add_moved_command(CLI::App& app, const std::string& name) {
  CLI::App* cmd = app.add_subcommand(name, "")->group("");
  cmd->allow_extras();
  cmd->callback(
      [name] { throw CLI::ValidationError(name, "the evaluation lab's command: run `fovea-eval " + name + "`"); });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fovea - FoveaRT foveation tool: point sets, interpolation, reconstruction, rendering"};
  app.require_subcommand(1);
  foveart::fovea::register_pointset(app);
  foveart::fovea::register_interpolate(app);
  foveart::fovea::register_reconstruct(app);
  foveart::fovea::register_render(app);
  for (const char* lab : {"pricelist", "accuracy", "motion", "bench-md"}) add_moved_command(app, lab);
  return foveart::toolkit::run_cli(app, argc, argv, "fovea");
}
