#pragma once
// Scenes are registered plugins: a name, a one-line description, declare_parameters and a factory.
// The command line builds the `Scene type` pattern from the registered names.

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  class RunContext;

  class Scene
  {
  public:
    virtual ~Scene() = default;
    /// Checks that need more than the parameter file (files exist, ...) without heavy work.
    virtual void validate() const {}
    /// Builds what the scene needs, solves, and writes its results through the context.
    virtual void run(RunContext &context) = 0;
  };

  struct SceneInfo
  {
    std::string                                                       name;
    std::string                                                       description;
    std::function<void(dealii::ParameterHandler &)>                   declare_parameters;
    std::function<std::unique_ptr<Scene>(dealii::ParameterHandler &)> create; // parses and checks
  };

  class SceneRegistry
  {
  public:
    static SceneRegistry &instance();

    void add(const SceneInfo &info);
    /// Throws with the list of valid names when `name` is not registered.
    const SceneInfo              &get(const std::string &name) const;
    bool                          has(const std::string &name) const;
    const std::vector<SceneInfo> &scenes() const { return registered; }
    std::string                   names_separated_by(const std::string &separator) const;

  private:
    std::vector<SceneInfo> registered;
  };

  /// Registers a scene at load time (ASPECT-style plugin registration).
  struct SceneRegistration
  {
    explicit SceneRegistration(const SceneInfo &info) { SceneRegistry::instance().add(info); }
  };
} // namespace nlmech

#define NLMECH_REGISTER_SCENE(identifier, info)                      \
  namespace                                                          \
  {                                                                  \
    const nlmech::SceneRegistration identifier##_registration(info); \
  }
