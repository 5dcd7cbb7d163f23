#include "reference/fixed_step.hpp"

#include <cmath>
#include <ctime>
#include <optional>
#include <stdexcept>

#include "solver/control.hpp"
#include "solver/limits.hpp"
#include "solver/mechanism/loops.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// The one failure rule after a step ending at t: the engine's complaint,
// then a non-finite state, then a speed beyond the blow-up bound.
bool checkStep(Trajectory& tr, double t, const std::string& complaint, const Eigen::VectorXd& q, const Eigen::VectorXd& u,
               double blowup_speed) {
  if (!complaint.empty()) markFailed(tr, t, Failure::Engine, complaint);
  else if (!q.allFinite() || !u.allFinite()) markFailed(tr, t, Failure::NonFinite, "non-finite state (NaN or Inf)");
  else if (u.size() && u.cwiseAbs().maxCoeff() > blowup_speed)
    markFailed(tr, t, Failure::BlowUp, "blow-up: max |u| exceeds the bound");
  return !tr.failed();
}

// An engine's stops as the harness sees them after every step (docs/theory.md
// §17): a coordinate beyond its stop opens an episode, entered at the
// crossing (linear between the two steps), with the speed of the last step
// inside; it closes at the first step back inside, with that step's speed,
// how far beyond it went and for how long. An episode still open at the end
// is kept as resting.
class StopEpisodes {
 public:
  explicit StopEpisodes(const Model& m) : m_(m), open_(m.limited.size()), g_(m.limited.size()), u_(m.limited.size()) {}
  bool active() const { return !m_.limited.empty(); }
  void start(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    for (size_t c = 0; c < m_.limited.size(); ++c) g_[c] = inside(c, q), u_[c] = u[m_.limited[c].u];
  }
  void step(double t, double dt, const Eigen::VectorXd& q, const Eigen::VectorXd& u, Trajectory& tr) {
    for (size_t c = 0; c < m_.limited.size(); ++c) {
      const double g = inside(c, q), v = u[m_.limited[c].u];
      std::optional<Impact>& e = open_[c];
      if (!e && g < 0) {  // crossed into the stop within this step
        e = Impact{};
        e->t = t - dt + dt * g_[c] / (g_[c] - g);
        e->coordinate = m_.limited[c].name;
        e->u_before = u_[c];
        e->energy_lost = std::numeric_limits<double>::quiet_NaN();  // the engine's stop: not measured
      }
      if (e) e->overshoot = std::max(e->overshoot, -g);
      if (e && g >= 0) {  // back inside: the rebound
        e->u_after = v;
        e->duration = t - dt + dt * g_[c] / (g_[c] - g) - e->t;
        keep(*e, tr);
        e.reset();
      }
      g_[c] = g, u_[c] = v;
    }
  }
  void finish(double t, Trajectory& tr) {
    for (size_t c = 0; c < open_.size(); ++c)
      if (std::optional<Impact>& e = open_[c]) {
        e->rests = true;
        e->u_after = u_[c];
        e->duration = t - e->t;
        keep(*e, tr);
        e.reset();
      }
  }

 private:
  double inside(size_t c, const Eigen::VectorXd& q) const {
    const LimitedCoordinate& l = m_.limited[c];
    return std::min(q[l.q] - l.lower, l.upper - q[l.q]);
  }
  static void keep(const Impact& e, Trajectory& tr) {
    if (tr.impacts.size() < kImpactsKept) tr.impacts.push_back(e);
    ++tr.impact_count;
  }
  const Model& m_;
  std::vector<std::optional<Impact>> open_;
  std::vector<double> g_, u_;  // per limited coordinate: inside() and its speed at the last step
};

}  // namespace

Trajectory runFixedStep(const Model& m, const CheckedRunSpec& run, FixedStepEngine& engine, const SampleObserver& observe) {
  const RunSpec& spec = run;
  const long n_out = outputIntervals(spec.t_end, spec.output_dt), per_output = stepsPerOutput(spec.output_dt, spec.dt);
  Trajectory tr = makeTrajectory(m, spec);
  Eigen::VectorXd q(m.nq), u(m.nu);
  std::vector<Pose> poses(m.n());
  double W = 0, P = 0, Pdot = 0, cpu = 0;  // W_diss, and the dampers' power and its rate at the current state
  std::optional<LoopMeter> meter;  // a mechanism's violation at the samples, by our g(q) and G u
  if (!m.loops.empty()) meter.emplace(m), tr.has_loops = true;
  auto sample = [&](double t) {
    double T = 0, V = 0;
    engine.sample(poses, T, V);  // first: an engine may complete its state here (MuJoCo's forward)
    engine.state(q, u);
    appendSample(tr, m, t, q.data(), u.data(), poses, {T + V, T, W});
    if (meter) meter->record(q.data(), u.data(), tr.loops);
  };
  sample(0.0);
  if (m.has_dampers) engine.dissipation(P, Pdot);
  // A controller, sampled every per_sample steps from the state the last step left (theory.md §18).
  ControlLoop control(m);
  const long per_sample = !control.active() ? 0 : control.sampled() ? stepsPerControlPeriod(control.period(), spec.dt) : 1;
  if (const std::string why = controlStepRefusal(m, spec.dt); !why.empty()) throw std::invalid_argument(why);  // refused before, by requireSettingsTaken
  Eigen::VectorXd q_start(control.active() ? m.nq : 0);
  StopEpisodes stops(m);  // an engine's own stops, watched after every step
  if (stops.active()) stops.start(q, u);
  // Timed as every owner is (solver/integrate.cpp, reference/simbody.cpp): over
  // whole output intervals, the steps with their per-step checks, the samples
  // apart. A clock read per step cost 1.4-1.6 us of CPU here (clock() is a
  // system call), charged to every engine step; per interval it is two reads
  // per output_dt.
  for (long k = 1; k <= n_out && !tr.failed(); ++k) {
    const double c0 = cpuSeconds();
    for (long s = 0; s < per_output; ++s) {
      if (per_sample && tr.steps % per_sample == 0) {
        control.sample(static_cast<double>(tr.steps) * spec.dt, q.data(), u.data());
        engine.applyControl(control.held());
      }
      if (per_sample) q_start = q;
      const std::string complaint = engine.step();
      ++tr.steps;
      engine.state(q, u);
      if (per_sample) W -= controlWork(m, control.held(), q_start, q);
      if (stops.active()) stops.step(static_cast<double>(tr.steps) * spec.dt, spec.dt, q, u, tr);
      if (const double apart = engine.jointSeparation(); !std::isnan(apart))  // NaN: the joints hold by construction
        tr.max_joint_separation = std::isnan(tr.max_joint_separation) ? apart : std::max(tr.max_joint_separation, apart);
      if (!checkStep(tr, static_cast<double>(tr.steps) * spec.dt, complaint, q, u, spec.options.blowup_speed)) break;
      if (!m.has_dampers) continue;
      double P1 = 0, Pdot1 = 0;
      engine.dissipation(P1, Pdot1);
      W += dissipatedOverStep(spec.dt, P, Pdot, P1, Pdot1);
      P = P1, Pdot = Pdot1;
    }
    cpu += cpuSeconds() - c0;
    if (tr.failed()) break;
    sample(k * spec.output_dt);
    if (observe) observe(k * spec.output_dt);
  }
  if (stops.active()) stops.finish(tr.t.empty() ? 0.0 : tr.t.back(), tr);
  tr.run_time_s = cpu;
  tr.rhs_evals = engine.evaluations();
  return tr;
}

}  // namespace em
