#pragma once
// The biphasic-sheet scene's parameters: the sheet (size, pins, membrane material), the strain
// limits (a formula in the material angle or measured samples, the curve tolerance), time stepping
// (schemes, Newton, projection) and collisions; with the limit curve b(alpha), the pinned vertices
// and the checks that refuse an infeasible setup before any step.

#include <deal.II/base/function_parser.h>
#include <deal.II/base/parameter_handler.h>

#include <nlmech/mesh/gmsh_mesh.h>
#include <nlmech/solvers/time/cloth_simulation.h>

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  struct BiphasicSheetSettings
  {
    double                                     size       = 0.5;
    unsigned int                               resolution = 20, directions = 4, frames = 40;
    std::vector<std::array<double, 3>>         pinned_points, pin_offsets;
    ShellMaterial                              material;
    std::string                                limit_expression;
    std::shared_ptr<dealii::FunctionParser<1>> limit_function;
    std::vector<std::pair<double, double>>     limit_samples; // (angle in [0, pi), limit)
    std::vector<ClothScheme>                   schemes;
    ClothSettings                              settings;
    ConicSettings                              cone_settings;
    double                                     end_time        = 2;
    double                                     curve_tolerance = 0.1;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    /// b(alpha): the formula, or the samples interpolated linearly and periodically over pi.
    double limit_at(double alpha) const;
    /// The sheet's vertices nearest to the pinned points (each within half a cell of one).
    std::vector<unsigned int> pinned_vertices(const RawSimplexMesh<3> &mesh) const;
    /// Refused before any step: a limit curve below 1 or not finite anywhere (a fine grid, not only
    /// the sampled directions), and pins moved farther apart than any state within the limits
    /// allows (no triangle stretches beyond the largest limit, plus the curve tolerance, or
    /// b_max / cos(pi / 2n) when only the n sampled directions are held).
    void check() const;
  };
} // namespace nlmech
