#include <nlmech/base/atomic_output.h>
#include <nlmech/base/run_context.h>
#include <nlmech/dim/element_output.h>
#include <nlmech/scenes/dim/dim_output.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace nlmech
{
  using namespace nlmech::dim;

  void write_samples_csv(RunContext &context, const std::string &test, const std::vector<Sample> &samples)
  {
    if (!context.is_root())
      return;
    constexpr double   degree = 3.14159265358979323846 / 180;
    std::ostringstream out;
    out << "key,theta_deg,kind,level,target_p,target_o,principal,orthogonal,"
        << (test == "in-plane" ? "E_xx,E_yy,E_xy" : "kappa_xx,kappa_yy,kappa_xy")
        << ",iterations,seconds,smallest_gap_mm\n";
    for (const auto &s : samples)
      {
        char line[512];
        std::snprintf(line, sizeof line, "%s,%.6g,%s,%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%u,%.4g,%.4g\n",
                      s.key().c_str(), s.theta / degree, to_string(s.kind).c_str(), s.level, s.target_p,
                      s.target_o, s.outcome.principal, s.outcome.orthogonal, s.point[0], s.point[1],
                      s.point[2], s.outcome.iterations, s.outcome.seconds, s.outcome.smallest_gap);
        out << line;
      }
    write_file_atomically(context.output.file("samples-" + test + ".csv"), out.str());
  }

  void report_directional_limits(RunContext &context, const std::vector<DirectionalLimits> &stretch,
                                 const std::vector<DirectionalLimits> &bend)
  {
    double c_min = 1e300, c_max = -1e300;
    for (const auto &s : stretch)
      if (s.negative_sampled)
        {
          const double c = travel_metric(s.positive_p, s.negative_p);
          c_min = std::min(c_min, c), c_max = std::max(c_max, c);
        }
    context.summary.add_number("stretch_directions", stretch.size());
    context.summary.add_number("bending_directions", bend.size());
    if (!stretch.empty())
      {
        context.summary.add_figure("stretch_limit_0deg", stretch[0].positive_p, "");
        // Only what was sampled: with `Positive only` there is no compression and no travel c.
        if (stretch[0].negative_sampled)
          context.summary.add_figure("compression_limit_0deg", stretch[0].negative_p, "");
        if (c_min <= c_max)
          {
            context.summary.add_figure("travel_c_min", c_min, "");
            context.summary.add_figure("travel_c_max", c_max, "");
          }
      }
    if (!bend.empty())
      context.summary.add_figure("kappa_positive_0deg", bend[0].positive_p, "1/mm");
    if (!bend.empty() && bend[0].negative_sampled)
      {
        context.summary.add_figure("kappa_negative_0deg", bend[0].negative_p, "1/mm");
        // |kappa+ + kappa-| relative: 0 for elements symmetric through the thickness.
        context.summary.add_figure(
            "bending_asymmetry_0deg",
            std::abs(bend[0].positive_p + bend[0].negative_p) /
                std::max({std::abs(bend[0].positive_p), std::abs(bend[0].negative_p), 1e-300}),
            "");
      }
  }

  void write_cell_states(RunContext &context, const Pattern &pattern, const NativeSolveSettings &settings,
                         const double far_strain, const Eigen::VectorXd &at_limit)
  {
    std::vector<std::array<int, 2>> block;
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        block.push_back({{i, j}});
    InPlaneTest test(pattern, 0.0, settings);
    write_elements_vtu(test.assembly(), test.state(), block, context.output.file("cell-rest.vtu"));
    if (at_limit.size() == test.state().size())
      {
        write_elements_vtu(test.assembly(), at_limit, block, context.output.file("cell-stretch-limit.vtu"));
        return;
      }
    test.solve(far_strain, settings.target_weight, 0, 0);
    write_elements_vtu(test.assembly(), test.state(), block, context.output.file("cell-stretch-limit.vtu"));
  }
} // namespace nlmech
