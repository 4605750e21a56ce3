// The calibration of issue 7 on the paper's set-up (docs/performance.md): 108 readings, the six
// parameters of Andres eq. 5, sigma = 0.035 mm. The budget is 50 ms for the 108-point case.
#include <benchmark/benchmark.h>

#include "redpost/calibration/identification.hpp"
#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/calibration/readings_csv.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

const Cell& andres() {
  static const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  return cell;
}

// The paper's perturbation (docs/calibration.md: angles read as degrees).
std::vector<CalibrationPoint> paper_readings() {
  const auto params = default_calibration_parameters();
  Eigen::VectorXd delta(6);
  delta << deg_to_rad(0.05), 0.01, deg_to_rad(0.06), 0.01, deg_to_rad(0.07), 0.08;
  const Cell truth = apply_parameters(andres(), params, parameter_values(andres(), params) + delta);
  std::vector<CalibrationPoint> pts = plan_calibration(andres());
  simulate_readings(truth, pts, 0.035, 1);
  return pts;
}

// Identification only: Gauss-Newton/LM with the AD Jacobian, observability, standard errors.
void BM_calibrate_108(benchmark::State& state) {
  const std::vector<CalibrationPoint> pts = paper_readings();
  const auto params = default_calibration_parameters();
  int iterations = 0;
  for (auto _ : state) {
    const CalibrationResult r = calibrate(andres(), params, pts);
    iterations = r.iterations;
    benchmark::DoNotOptimize(r.values.data());
  }
  state.counters["gn_iterations"] = iterations;
}
BENCHMARK(BM_calibrate_108)->Unit(benchmark::kMillisecond);

// The same with the Huber loss (IRLS).
void BM_calibrate_108_huber(benchmark::State& state) {
  const std::vector<CalibrationPoint> pts = paper_readings();
  const auto params = default_calibration_parameters();
  CalibrationOptions opt;
  opt.loss = RobustLoss::huber;
  for (auto _ : state) {
    const CalibrationResult r = calibrate(andres(), params, pts, opt);
    benchmark::DoNotOptimize(r.values.data());
  }
}
BENCHMARK(BM_calibrate_108_huber)->Unit(benchmark::kMillisecond);

// Reading the 108 rows in the commanded-pose form: the arm joints of every row are solved on
// the nominal model, as the controller did.
void BM_read_readings_108(benchmark::State& state) {
  ReadingsWriteOptions w;
  const std::string text = format_readings_csv(andres(), paper_readings(), w);
  for (auto _ : state) {
    const auto pts = parse_readings_csv(text, "bench.csv", andres());
    benchmark::DoNotOptimize(pts.data());
  }
}
BENCHMARK(BM_read_readings_108)->Unit(benchmark::kMillisecond);

// The plan: 108 commanded frames solved on the nominal model.
void BM_plan_108(benchmark::State& state) {
  for (auto _ : state) {
    const auto pts = plan_calibration(andres());
    benchmark::DoNotOptimize(pts.data());
  }
}
BENCHMARK(BM_plan_108)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
