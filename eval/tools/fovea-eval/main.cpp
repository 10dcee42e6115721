// fovea-eval: the evaluation lab's front end, apart from the product's `fovea`.
#include <eval/cmd_motion.hpp>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  CLI::App app{"fovea-eval - FoveaRT evaluation lab: sequences over a scripted motion against a converged reference"};
  app.require_subcommand(1);
  foveart::eval::register_motion(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    const auto subs = app.get_subcommands();
    std::fprintf(stderr, "fovea-eval %s: error: %s\n", subs.empty() ? "" : subs.front()->get_name().c_str(), e.what());
    return 1;
  }
  return 0;
}
