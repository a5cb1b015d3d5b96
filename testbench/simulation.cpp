#include "simulation.hpp"

#include <filesystem>
#include <memory>
#include <thread>

#include "hw/top.hpp"
#include "latency.hpp"
#include "run_report.hpp"
#include "scoreboard.hpp"
#include "traces/vcd_writer.hpp"

namespace tigris {

std::string gtkw_path(const std::string& vcd_path) {
  return std::filesystem::path(vcd_path).replace_extension(".gtkw").string();
}

int default_sim_threads() { return std::thread::hardware_concurrency() >= 2 ? 2 : 1; }

std::vector<SimOutcome> simulate(const std::vector<SimSetup>& setups, const SimProgress& progress) {
  struct Bench {
    std::unique_ptr<hw::TigrisAccelerator> accel;
    std::unique_ptr<HostDriver> host;
    std::unique_ptr<sc_core::sc_signal<bool>> irq;
    std::unique_ptr<VcdWriter> vcd;
    std::unique_ptr<VisitRecorder> recorder;
    std::unique_ptr<LatencyRecorder> latency;
    std::unique_ptr<SampleController> windows;
  };
  std::vector<Bench> benches;
  std::vector<SimOutcome> out(setups.size());
  for (std::size_t i = 0; i < setups.size(); ++i) {
    const SimSetup& s = setups[i];
    const std::string tag = setups.size() == 1 ? "" : std::to_string(i);
    Bench b;
    b.accel = std::make_unique<hw::TigrisAccelerator>(("tigris" + tag).c_str(), s.config,
                                                      hw::HostOptions{s.reverse_construction, s.sim_threads >= 2});
    b.host = std::make_unique<HostDriver>(("host" + tag).c_str(), *s.image, *s.queries, s.num_points, s.job);
    b.irq = std::make_unique<sc_core::sc_signal<bool>>(("irq" + tag).c_str());
    b.accel->irq(*b.irq);
    b.host->irq(*b.irq);
    b.host->socket.bind(b.accel->host);
    b.recorder = std::make_unique<VisitRecorder>();
    b.accel->attach_observer(*b.recorder);
    b.accel->attach_hint(*b.recorder);
    b.latency = std::make_unique<LatencyRecorder>();
    b.accel->attach_observer(*b.latency);
    if (s.job.runs > 1) {
      const hw::TigrisAccelerator* a = b.accel.get();
      const HostDriver* h = b.host.get();
      const VisitRecorder* rec = b.recorder.get();
      b.host->on_run_done([a, h, rec, o = &out[i]](int) {
        o->runs.push_back({h->cycles(), h->results(), rec->visits(), run_stats_json(*a, h->cycles())});
      });
    }
    if (s.sampling) {
      b.windows = std::make_unique<SampleController>(*s.sampling, *b.accel, s.sampling_work);
      b.accel->attach_observer(*b.windows);
    }
    if (progress && setups.size() == 1) b.accel->set_progress(progress);
    if (s.test_hook) s.test_hook(*b.accel);
    for (hw::JobObserver* o : s.observers) b.accel->attach_observer(*o);
    if (!s.vcd_path.empty()) {
      b.vcd = std::make_unique<VcdWriter>(s.vcd_path);
      b.vcd->set_comment(s.provenance);
      b.accel->attach_waves(*b.vcd);
    }
    benches.push_back(std::move(b));
  }
  sc_core::sc_start();
  for (std::size_t i = 0; i < setups.size(); ++i) {
    hw::TigrisAccelerator& a = *benches[i].accel;
    HostDriver& h = *benches[i].host;
    SimOutcome& o = out[i];
    o.finished = h.finished();
    o.error = !a.error().empty() ? "the accelerator rejected the job: " + a.error() : h.error();
    if (!o.finished && o.error.empty()) o.deadlock = a.describe_state();
    o.results = h.take_results();
    o.cycles = h.cycles();
    if (setups[i].sampling && o.finished && o.error.empty())
      o.cycles = apply_estimate(*setups[i].sampling, *benches[i].windows, a, o.cycles, o.sampling);
    o.visits = benches[i].recorder->take_visits();
    nlohmann::json stats = run_stats_json(a, o.cycles);
    o.units = std::move(stats["units"]);
    o.buffers = std::move(stats["buffers"]);
    o.energy = std::move(stats["energy_pj"]);
    o.power_w = std::move(stats["power_w"]);
    o.area = std::move(stats["area_mm2"]);
    o.latency = benches[i].latency->json();
    if (benches[i].vcd) {
      benches[i].vcd->close();
      const std::uint64_t start_ps =
          static_cast<std::uint64_t>(a.start_cycle() * a.config().period() / sc_core::sc_time(1, sc_core::SC_PS));
      if (!setups[i].gtkw_path.empty())
        write_gtkw(setups[i].gtkw_path, setups[i].vcd_path, *benches[i].vcd, start_ps, setups[i].provenance);
    }
  }
  return out;
}

}  // namespace tigris
