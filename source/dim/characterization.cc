#include <deal.II/base/exceptions.h>

#include <nlmech/base/exceptions.h>
#include <nlmech/dim/characterization.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace nlmech::dim
{
  namespace
  {
    std::pair<Eigen::Vector2d, Eigen::Vector2d> principal_frame(const double theta)
    {
      return {Eigen::Vector2d(std::cos(theta), std::sin(theta)),
              Eigen::Vector2d(-std::sin(theta), std::cos(theta))};
    }

    TestOutcome minimise(const Model &model, const RigidAssembly &assembly, Eigen::VectorXd &q,
                         const NativeSolveSettings &settings, const std::string &what)
    {
      const auto     start = std::chrono::steady_clock::now();
      NewtonSettings newton;
      newton.max_iterations     = settings.max_iterations;
      newton.step_tolerance     = settings.step_tolerance;
      newton.relative_tolerance = 1e-8;
      // Or: the reached strains (curvatures) have settled and the forces nearly balance (see
      // NativeSolveSettings::parameter_tolerance).
      std::vector<Eigen::Vector2d> history;
      const Eigen::Index           i0 = assembly.parameter_index(0), i1 = assembly.parameter_index(1);
      newton.converged = [&](const Eigen::VectorXd &x, const double g, const double g0) {
        history.emplace_back(x[i0], x[i1]);
        if (history.size() < 11 || g > settings.force_tolerance * g0)
          return false;
        double change = 0;
        for (std::size_t k = history.size() - 11; k < history.size(); ++k)
          change = std::max(change, (history[k] - history.back()).lpNorm<Eigen::Infinity>());
        return change <= settings.parameter_tolerance;
      };
      DiagonalShift::Settings shift;
      shift.grow_on_short_steps = true; // sliding contacts otherwise crawl at collision-bounded steps
      shift.metric              = assembly.motion_metric(q);
      NewtonSolver solver(newton, std::make_shared<DiagonalShift>(shift));
      TestOutcome  outcome;
      try
        {
          const auto result  = solver.minimize(model, q);
          outcome.iterations = result.iterations;
        }
      catch (const std::exception &e)
        {
          AssertThrow(false, dealii::ExcMessage(what + ": the native-scale solve failed: " + message_of(e)));
        }
      outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      outcome.smallest_gap =
          assembly.smallest_gap(q, settings.contact.separation + settings.contact.dhat).gap;
      outcome.principal  = q[assembly.parameter_index(0)];
      outcome.orthogonal = q[assembly.parameter_index(1)];
      return outcome;
    }
  } // namespace

  Eigen::Vector3d green_strain(const Eigen::Matrix2d &F)
  {
    const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
    return {E(0, 0), E(1, 1), E(0, 1)};
  }

  Eigen::Vector3d green_strain(const double theta, const double eps_p, const double eps_o)
  {
    const auto [dp, d_o] = principal_frame(theta);
    const Eigen::Matrix2d U =
        Eigen::Matrix2d::Identity() + eps_p * dp * dp.transpose() + eps_o * d_o * d_o.transpose();
    return green_strain(U);
  }

  Eigen::Vector3d curvature_tensor(const double theta, const double kappa_p, const double kappa_o)
  {
    const auto [dp, d_o]    = principal_frame(theta);
    const Eigen::Matrix2d K = kappa_p * dp * dp.transpose() + kappa_o * d_o * d_o.transpose();
    return {K(0, 0), K(1, 1), K(0, 1)};
  }

  Eigen::Matrix2d cell_deformation_gradient(const Eigen::Vector2d &t1, const Eigen::Vector2d &t2,
                                            const Eigen::Vector2d &tbar1, const Eigen::Vector2d &tbar2)
  {
    Eigen::Matrix2d T, Tbar;
    T << t1, t2;
    Tbar << tbar1, tbar2;
    return T * Tbar.inverse();
  }

  double travel_metric(const double eps_stretch, const double eps_compress)
  {
    return (eps_stretch - eps_compress) / (1 + eps_compress);
  }

  InPlaneTest::InPlaneTest(const Pattern &pattern, const double theta, NativeSolveSettings s)
      : angle(theta)
      , settings(s)
  {
    const auto [dp, d_o] = principal_frame(theta);
    cell                 = periodic_cell(pattern, {dp * dp.transpose(), d_o * d_o.transpose()});
    check_initial_state(*cell.assembly, cell.q, settings.contact.separation);
    q = cell.q;
  }

  TestOutcome InPlaneTest::solve(const double target_p, const double weight_p, const double target_o,
                                 const double weight_o, const bool continue_from_last)
  {
    if (!continue_from_last)
      q = cell.q;
    const auto &assembly = *cell.assembly;
    Model       model(assembly.n_unknowns());
    model.add_term(std::make_shared<ContactBarrier>(cell.assembly, settings.contact));
    model.add_term(std::make_shared<ParameterTarget>(assembly.parameter_index(0),
                                                     std::vector<double>{target_p, target_o},
                                                     std::vector<double>{weight_p, weight_o}));
    // A translation of the whole cell is a null mode: hold the first element's centre.
    for (unsigned k = 0; k < 3; ++k)
      model.fix(k, q[k]);
    std::ostringstream what;
    what << "In-plane test (theta = " << angle * 180 / M_PI << " deg, targets " << target_p << ", "
         << target_o << ")";
    return minimise(model, assembly, q, settings, what.str());
  }

  BendingTest::BendingTest(const Pattern &pattern, const unsigned int n_elements, const double theta,
                           NativeSolveSettings s)
      : angle(theta)
      , settings(s)
  {
    patch          = finite_patch(pattern, n_elements, PatchShape::disk, Placement::paraboloid);
    const double c = std::cos(theta), sn = std::sin(theta);
    // (A, B, C) = A' (c^2, s^2, 2 c s) + B' (s^2, c^2, -2 c s): z = A' x'^2 + B' y'^2 in the rotated frame.
    patch.assembly->set_curvature_basis(
        {Eigen::Vector3d(c * c, sn * sn, 2 * c * sn), Eigen::Vector3d(sn * sn, c * c, -2 * c * sn)});
    patch.q.conservativeResize(patch.assembly->n_unknowns());
    patch.q.tail(patch.assembly->n_parameters()).setZero();
    check_initial_state(*patch.assembly, patch.q, settings.contact.separation);
    q = patch.q;
    for (unsigned b = 0; b < patch.assembly->n_bodies(); ++b)
      gravity_forces.emplace_back(0, 0, -patch.assembly->shape(b).mass * settings.gravity);
  }

  double BendingTest::gravity_load() const
  {
    const auto [dp, d_o] = principal_frame(angle);
    double along = 0, across = 0;
    for (unsigned b = 0; b < patch.assembly->n_bodies(); ++b)
      {
        const Eigen::Vector2d x(patch.q[6 * b], patch.q[6 * b + 1]);
        const double          weight = -gravity_forces[b].z();
        along += weight * std::pow(dp.dot(x), 2), across += weight * std::pow(d_o.dot(x), 2);
      }
    return std::max(along, across);
  }

  TestOutcome BendingTest::solve(const double target_p, const double weight_p, const double target_o,
                                 const double weight_o, const bool continue_from_last)
  {
    if (!continue_from_last)
      q = patch.q;
    const auto &assembly = *patch.assembly;
    Model       model(assembly.n_unknowns());
    model.add_term(std::make_shared<ContactBarrier>(patch.assembly, settings.contact));
    model.add_term(std::make_shared<CentreForces>(patch.assembly, gravity_forces));
    // Parameters are A', B' = kappa / 2.
    model.add_term(std::make_shared<ParameterTarget>(assembly.parameter_index(0),
                                                     std::vector<double>{0.5 * target_p, 0.5 * target_o},
                                                     std::vector<double>{weight_p, weight_o}));
    // Centres stay on the paraboloid; the central element holds the patch in place.
    for (unsigned b = 0; b < assembly.n_bodies(); ++b)
      model.fix(6 * b + 2, 0.0);
    model.fix(0, q[0]), model.fix(1, q[1]), model.fix(5, q[5]);
    std::ostringstream what;
    what << "Bending test (theta = " << angle * 180 / M_PI << " deg, targets " << target_p << ", " << target_o
         << ")";
    TestOutcome outcome = minimise(model, assembly, q, settings, what.str());
    outcome.principal *= 2, outcome.orthogonal *= 2;
    return outcome;
  }
} // namespace nlmech::dim

#include <deal.II/base/mpi.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/for_each_job.h>

#include <filesystem>
#include <fstream>
#include <mutex>

namespace nlmech::dim
{
  std::string to_string(const SampleKind kind)
  {
    switch (kind)
      {
        case SampleKind::positive: return "positive";
        case SampleKind::negative: return "negative";
        case SampleKind::level_up: return "level-up";
        default: return "level-down";
      }
  }

  std::string Sample::key() const
  {
    char name[96];
    std::snprintf(name, sizeof name, "%s-d%03u-%s-l%02u", test.c_str(), direction,
                  dim::to_string(kind).c_str(), level);
    return name;
  }

  bool reached_far_target(const Sample &sample, const double tolerance)
  {
    const bool principal_driven = sample.kind == SampleKind::positive || sample.kind == SampleKind::negative;
    const double target         = principal_driven ? sample.target_p : sample.target_o;
    const double reached        = principal_driven ? sample.outcome.principal : sample.outcome.orthogonal;
    return target != 0 && reached / target >= 1 - tolerance;
  }

  namespace
  {
    namespace fs = std::filesystem;

    /// FNV-1a, 64 bits: detects edits and damage (not an adversary).
    std::string checksum(const std::string &text)
    {
      std::uint64_t h = 1469598103934665603ull;
      for (const unsigned char c : text)
        h = (h ^ c) * 1099511628211ull;
      char hex[17];
      std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
      return hex;
    }

    std::string numbers_of(const Sample &s)
    {
      char line[512];
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g %u %.6g %.6g", s.theta, s.target_p,
                    s.target_o, s.outcome.principal, s.outcome.orthogonal, s.outcome.iterations,
                    s.outcome.seconds, s.outcome.smallest_gap);
      return line;
    }

    /// The sample file: its numbers, the code version and a checksum over both, the key and the plan.
    std::string record_of(const Sample &s, const std::string &fingerprint)
    {
      const std::string numbers = numbers_of(s), version = code_version();
      return numbers + "\ncode " + version + "\nchecksum " +
             checksum(fingerprint + "\n" + s.key() + "\n" + numbers + "\n" + version) + "\n";
    }

    enum class RecordState
    {
      valid,
      missing,
      stale,  // another code version
      damaged // unreadable, checksum mismatch, or physically invalid
    };

    RecordState read_record(const std::string &path, Sample &s, const std::string &fingerprint)
    {
      std::ifstream in(path);
      if (!in)
        return RecordState::missing;
      std::string numbers, code_line, checksum_line;
      if (!std::getline(in, numbers) || !std::getline(in, code_line) || !std::getline(in, checksum_line) ||
          code_line.rfind("code ", 0) != 0 || checksum_line.rfind("checksum ", 0) != 0)
        return RecordState::damaged;
      const std::string version = code_line.substr(5);
      if (checksum_line.substr(9) != checksum(fingerprint + "\n" + s.key() + "\n" + numbers + "\n" + version))
        return RecordState::damaged;
      if (version != code_version())
        return RecordState::stale;
      Sample             r = s;
      std::istringstream line(numbers);
      if (!(line >> r.theta >> r.target_p >> r.target_o >> r.outcome.principal >> r.outcome.orthogonal >>
            r.outcome.iterations >> r.outcome.seconds >> r.outcome.smallest_gap))
        return RecordState::damaged;
      // The job it claims to be, and a state that can exist (no intersection: gap >= 0).
      if (!std::isfinite(r.outcome.principal) || !std::isfinite(r.outcome.orthogonal) ||
          !(r.outcome.smallest_gap >= 0) || std::abs(r.theta - s.theta) > 1e-12 || r.target_p != s.target_p ||
          r.target_o != s.target_o)
        return RecordState::damaged;
      s = r;
      return RecordState::valid;
    }
    void set_point(Sample &s)
    {
      s.point = s.test == "in-plane" ? green_strain(s.theta, s.outcome.principal, s.outcome.orthogonal)
                                     : curvature_tensor(s.theta, s.outcome.principal, s.outcome.orthogonal);
    }
  } // namespace

  std::vector<Sample>
  sample_strain_space(const Pattern &pattern, const std::string &test, const SamplingPlan &plan,
                      const NativeSolveSettings &settings, const std::string &checkpoint_directory,
                      MPI_Comm comm, const std::function<void(unsigned, unsigned, const Sample &)> &progress,
                      SamplingStatistics *statistics)
  {
    AssertThrow(test == "in-plane" || test == "bending",
                dealii::ExcMessage("Sampling: the test is 'in-plane' or 'bending', not '" + test + "'."));
    const unsigned directions = plan.directions_of(test);
    AssertThrow(directions >= 1, dealii::ExcMessage("Sampling: needs at least one direction."));
    const unsigned rank = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned size = dealii::Utilities::MPI::n_mpi_processes(comm);
    std::string    mismatch;
    // plan.txt: the plan's fingerprint, then the code version that wrote the samples.
    const std::string plan_text = plan.fingerprint + "code " + code_version() + "\n";
    if (rank == 0)
      {
        fs::create_directories(checkpoint_directory);
        const std::string path = checkpoint_directory + "/plan.txt";
        if (!fs::exists(path))
          {
            bool samples_present = false;
            for (const auto &entry : fs::directory_iterator(checkpoint_directory))
              samples_present = samples_present || entry.path().extension() == ".sample";
            if (samples_present)
              mismatch = "Sampling: the checkpoint directory '" + checkpoint_directory +
                         "' holds samples but no plan.txt, so what made them cannot be told; remove it or "
                         "choose another 'Checkpoint directory'.";
            else
              write_file_atomically(path, plan_text);
          }
        else
          {
            std::ifstream     in(path);
            const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            const auto        code = kept.rfind("code ");
            if (kept.substr(0, code == std::string::npos ? kept.size() : code) != plan.fingerprint)
              mismatch =
                  "Sampling: the checkpoint directory '" + checkpoint_directory +
                  "' holds samples of a different material, contact or sampling plan (see its plan.txt); "
                  "remove it or choose another 'Checkpoint directory'.";
            else if (kept != plan_text)
              write_file_atomically(path, plan_text); // another code version: its samples are redone
          }
      }
    mismatch = dealii::Utilities::MPI::broadcast(comm, mismatch, 0);
    AssertThrow(mismatch.empty(), dealii::ExcMessage(mismatch));
    SamplingStatistics counts;
    const double       far = test == "in-plane" ? plan.far_strain : plan.far_curvature;
    const double       w = settings.target_weight, hold = settings.hold_weight;
    unsigned           new_samples = 0;

    // One phase: run the jobs not yet checkpointed, round-robin over the ranks, then read all.
    auto run_phase = [&](std::vector<Sample> &jobs) {
      std::vector<std::size_t> open;
      for (std::size_t j = 0; j < jobs.size(); ++j)
        {
          Sample            probe = jobs[j];
          const RecordState state =
              read_record(checkpoint_directory + "/" + jobs[j].key() + ".sample", probe, plan.fingerprint);
          if (state == RecordState::valid)
            ++counts.resumed;
          else
            {
              open.push_back(j);
              counts.stale += state == RecordState::stale;
              counts.damaged += state == RecordState::damaged;
            }
        }
      // Every rank must see the same open jobs before anybody writes a new sample.
      MPI_Barrier(comm);
      // This rank's jobs run on its task threads, each thread taking the next open job; a failure
      // stops the ones not yet started, and the first failed job (in job order) is reported.
      std::vector<std::size_t> mine;
      for (std::size_t k = rank; k < open.size(); k += size)
        mine.push_back(open[k]);
      std::mutex  guard;
      std::string error;
      std::size_t error_job = jobs.size();
      unsigned    done = 0, started = new_samples;
      for_each_job(mine.size(), [&](const std::size_t i) {
        {
          const std::lock_guard<std::mutex> lock(guard);
          // After a failure only the jobs before it in job order start: every rank then has run
          // all its jobs before its first failure, whatever the thread count.
          if (mine[i] > error_job || (plan.stop_after > 0 && started >= plan.stop_after))
            return;
          ++started;
        }
        Sample &s = jobs[mine[i]];
        try
          {
            const bool uniaxial = s.kind == SampleKind::positive || s.kind == SampleKind::negative;
            // One solve from rest; if it fails, once more in two stages (half the way to the target
            // first, then on from there), which avoids most slides that stall.
            auto drive = [&](auto &t) {
              try
                {
                  return uniaxial ? t.solve(s.target_p, w, 0.0, 0.0)
                                  : t.solve(s.target_p, hold, s.target_o, w);
                }
              catch (const std::exception &)
                {
                  if (uniaxial)
                    t.solve(0.5 * s.target_p, w, 0.0, 0.0);
                  else
                    t.solve(s.target_p, hold, 0.5 * s.target_o, w);
                  TestOutcome o = uniaxial ? t.solve(s.target_p, w, 0.0, 0.0, true)
                                           : t.solve(s.target_p, hold, s.target_o, w, true);
                  return o;
                }
            };
            if (test == "in-plane")
              {
                InPlaneTest t(pattern, s.theta, settings);
                s.outcome       = drive(t);
                s.outcome.state = t.state();
              }
            else
              {
                BendingTest t(pattern, plan.patch_elements, s.theta, settings);
                s.outcome       = drive(t);
                s.outcome.state = t.state();
              }
            AssertThrow(std::isfinite(s.outcome.principal) && std::isfinite(s.outcome.orthogonal),
                        dealii::ExcMessage("Sampling: a test returned a non-finite result."));
            write_file_atomically(checkpoint_directory + "/" + s.key() + ".sample",
                                  record_of(s, plan.fingerprint));
            const std::lock_guard<std::mutex> lock(guard);
            ++new_samples, ++counts.computed;
            if (progress)
              progress(++done, unsigned(mine.size()), s);
          }
        catch (const std::exception &e)
          {
            const std::lock_guard<std::mutex> lock(guard);
            if (mine[i] < error_job)
              error = "Sample " + s.key() + ": " + message_of(e), error_job = mine[i];
          }
      });
      // Agree on errors and on an early stop before anybody reads the checkpoint.
      // The failure reported is the first in job order over all ranks.
      const auto  errors    = dealii::Utilities::MPI::all_gather(comm, std::make_pair(error_job, error));
      std::size_t first_job = jobs.size();
      for (const auto &[job, e] : errors)
        {
          AssertThrow(e.empty() || statistics, dealii::ExcMessage(e));
          if (!e.empty() && job < first_job)
            counts.failure = e, first_job = job;
        }
      const unsigned stopped =
          dealii::Utilities::MPI::max(unsigned(plan.stop_after > 0 && new_samples >= plan.stop_after), comm);
      AssertThrow(stopped == 0,
                  dealii::ExcMessage("Sampling stopped after " + std::to_string(plan.stop_after) +
                                     " new samples, as asked ('Stop after'); run again to resume."));
      if (!counts.failure.empty())
        {
          // Keep the samples that were finished, in job order, for the partial result.
          std::vector<Sample> finished;
          for (auto &s : jobs)
            if (read_record(checkpoint_directory + "/" + s.key() + ".sample", s, plan.fingerprint) ==
                RecordState::valid)
              {
                set_point(s);
                finished.push_back(s);
              }
          jobs = finished;
          return false;
        }
      for (auto &s : jobs)
        {
          AssertThrow(
              read_record(checkpoint_directory + "/" + s.key() + ".sample", s, plan.fingerprint) ==
                  RecordState::valid,
              dealii::ExcMessage("Sampling: the checkpoint of " + s.key() +
                                 " is missing, unreadable or fails its checksum after it was written."));
          set_point(s);
        }
      return true;
    };

    std::vector<Sample> phase1;
    for (unsigned d = 0; d < directions; ++d)
      for (const SampleKind kind : {SampleKind::positive, SampleKind::negative})
        if (kind == SampleKind::positive || !plan.positive_only)
          {
            Sample s;
            s.test = test, s.direction = d, s.kind = kind, s.theta = M_PI * d / directions;
            s.target_p = kind == SampleKind::positive ? far : -far;
            phase1.push_back(s);
          }
    const bool phase1_done = run_phase(phase1);
    if (statistics)
      *statistics = counts;
    if (plan.positive_only || !phase1_done)
      return phase1;
    std::vector<Sample> phase2;
    for (unsigned d = 0; d < directions; ++d)
      for (unsigned l = 1; l <= plan.levels; ++l)
        for (const SampleKind kind : {SampleKind::level_up, SampleKind::level_down})
          {
            const double hi = phase1[2 * d].outcome.principal, lo = phase1[2 * d + 1].outcome.principal;
            Sample       s;
            s.test = test, s.direction = d, s.level = l, s.kind = kind, s.theta = M_PI * d / directions;
            s.target_p = lo + (hi - lo) * l / (plan.levels + 1);
            s.target_o = kind == SampleKind::level_up ? far : -far;
            phase2.push_back(s);
          }
    run_phase(phase2);
    if (statistics)
      *statistics = counts;
    phase1.insert(phase1.end(), phase2.begin(), phase2.end());
    return phase1;
  }

  double raise_bending_weights(const Pattern &pattern, const SamplingPlan &plan,
                               NativeSolveSettings &settings)
  {
    double         load       = 0;
    const unsigned directions = std::max(plan.directions_of("bending"), 1u);
    for (unsigned d = 0; d < directions; ++d)
      load = std::max(
          load, BendingTest(pattern, plan.patch_elements, M_PI * d / directions, settings).gravity_load());
    // 2 G / w at most 0.5 % of the far curvature: the measured shortfall is up to about 1.5 times
    // 2 G / w (the load grows as the patch bends), so within 1 %.
    const double needed = 2 * load / (0.005 * plan.far_curvature);
    if (!(needed > settings.target_weight))
      return 1;
    const double factor = needed / settings.target_weight;
    settings.target_weight *= factor, settings.hold_weight *= factor;
    return factor;
  }

  std::vector<DirectionalLimits> directional_limits(const std::vector<Sample> &samples,
                                                    const unsigned int         directions)
  {
    std::vector<DirectionalLimits> limits(directions);
    for (const auto &s : samples)
      {
        if (s.direction >= directions)
          continue;
        auto &l = limits[s.direction];
        l.theta = s.theta;
        if (s.kind == SampleKind::positive)
          l.positive_p = s.outcome.principal, l.positive_o = s.outcome.orthogonal;
        else if (s.kind == SampleKind::negative)
          l.negative_p = s.outcome.principal, l.negative_o = s.outcome.orthogonal, l.negative_sampled = true;
      }
    return limits;
  }

  std::string limits_table(const std::vector<DirectionalLimits> &stretch,
                           const std::vector<DirectionalLimits> &bending)
  {
    // Direction d of n lies at d / n of a half turn: rows at the distinct fractions of both.
    std::vector<std::pair<double, std::array<int, 2>>> rows; // angle [deg], index in stretch, bending
    const auto row_at = [&](const double deg) -> std::array<int, 2> & {
      for (auto &r : rows)
        if (std::abs(r.first - deg) < 1e-9)
          return r.second;
      rows.push_back({deg, {{-1, -1}}});
      return rows.back().second;
    };
    for (std::size_t d = 0; d < stretch.size(); ++d)
      row_at(180.0 * d / stretch.size())[0] = d;
    for (std::size_t d = 0; d < bending.size(); ++d)
      row_at(180.0 * d / bending.size())[1] = d;
    std::sort(rows.begin(), rows.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
    std::ostringstream out;
    out << "theta_deg,eps_stretch,eps_o_at_stretch,eps_compress,eps_o_at_compress,travel_c,"
           "kappa_positive,kappa_o_at_positive,kappa_negative,kappa_o_at_negative\n";
    char field[160];
    for (const auto &[deg, index] : rows)
      {
        std::snprintf(field, sizeof field, "%.6g", deg);
        out << field;
        if (index[0] >= 0)
          {
            const auto &s = stretch[index[0]];
            if (s.negative_sampled)
              std::snprintf(field, sizeof field, ",%.9g,%.9g,%.9g,%.9g,%.9g", s.positive_p, s.positive_o,
                            s.negative_p, s.negative_o, travel_metric(s.positive_p, s.negative_p));
            else // only what was sampled: no compression, so no travel either
              std::snprintf(field, sizeof field, ",%.9g,%.9g,,,", s.positive_p, s.positive_o);
            out << field;
          }
        else
          out << ",,,,,";
        if (index[1] >= 0)
          {
            const auto &b = bending[index[1]];
            if (b.negative_sampled)
              std::snprintf(field, sizeof field, ",%.9g,%.9g,%.9g,%.9g", b.positive_p, b.positive_o,
                            b.negative_p, b.negative_o);
            else
              std::snprintf(field, sizeof field, ",%.9g,%.9g,,", b.positive_p, b.positive_o);
            out << field;
          }
        else
          out << ",,,,";
        out << "\n";
      }
    return out.str();
  }
} // namespace nlmech::dim
