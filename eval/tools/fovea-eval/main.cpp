// fovea-eval: the evaluation lab's front end, apart from the product's `fovea`.
#include <eval/bench_markdown.hpp>
#include <eval/cmd_accuracy.hpp>
#include <eval/cmd_density.hpp>
#include <eval/cmd_motion.hpp>
#include <eval/cmd_perceptual.hpp>
#include <eval/cmd_pricelist.hpp>
#include <toolkit/run_cli.hpp>

int main(int argc, char** argv) {
  CLI::App app{
      "fovea-eval - FoveaRT evaluation lab: accuracy against a converged reference, sequences over a scripted "
      "motion, the price list, the perceptual metric of an image pair, the density it does not see, benchmark results as markdown"};
  app.require_subcommand(1);
  foveart::eval::register_accuracy(app);
  foveart::eval::register_density(app);
  foveart::eval::register_motion(app);
  foveart::eval::register_pricelist(app);
  foveart::eval::register_perceptual(app);
  foveart::eval::register_bench_md(app);
  return foveart::toolkit::run_cli(app, argc, argv, "fovea-eval");
}
