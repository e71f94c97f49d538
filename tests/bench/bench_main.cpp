// marionette_bench's main: Google Benchmark's own main, except that the program exits 1
// when any benchmark reported an error (SkipWithError: missing data, a character that
// cannot walk, ...). Otherwise such a benchmark leaves a line saying "ERROR OCCURRED",
// no figure, and exit status 0, and scripts/benchmarks would go on without the figure.
// A filter that matches no benchmark fails too.
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

// Passes everything on to the reporter the command line chose (--benchmark_format) and
// remembers the names of the runs that reported an error.
class ErrorRecordingReporter : public benchmark::BenchmarkReporter {
 public:
  explicit ErrorRecordingReporter(benchmark::BenchmarkReporter* display) : display_(display) {}

  bool ReportContext(const Context& context) override { return display_->ReportContext(context); }

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs)
      if (run.error_occurred) failed_.push_back(run.benchmark_name() + ": " + run.error_message);
    display_->ReportRuns(runs);
  }

  void Finalize() override { display_->Finalize(); }

  const std::vector<std::string>& failed() const { return failed_; }

 private:
  std::unique_ptr<benchmark::BenchmarkReporter> display_;
  std::vector<std::string> failed_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  ErrorRecordingReporter reporter(benchmark::CreateDefaultDisplayReporter());
  const size_t matched = benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  if (matched == 0) {  // a mistyped --benchmark_filter: no figure at all
    std::cerr << "marionette_bench: no benchmark matches the filter\n";
    return 1;
  }
  if (reporter.failed().empty()) return 0;
  std::cerr << "marionette_bench: " << reporter.failed().size() << " run(s) reported an error:\n";
  for (const std::string& f : reporter.failed()) std::cerr << "  " << f << "\n";
  return 1;
}
