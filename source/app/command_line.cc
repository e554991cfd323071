#include <nlmech/app/command_line.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>

#include <boost/core/demangle.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <typeinfo>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    const char *usage =
        "usage: nlmech FILE.prm [--output-directory DIR]   run the scene named in FILE.prm\n"
        "       nlmech --validate FILE.prm                 parse and check FILE.prm only\n"
        "       nlmech --print-parameters SCENE            print SCENE's documented parameters\n"
        "       nlmech --list-scenes                       list the registered scenes\n"
        "       --threads N (anywhere)                     at most N threads per MPI rank (default: every "
        "core)\n";

    std::string trim(const std::string &s)
    {
      const auto begin = s.find_first_not_of(" \t\r\n");
      if (begin == std::string::npos)
        return "";
      return s.substr(begin, s.find_last_not_of(" \t\r\n") - begin + 1);
    }

    void declare_common_parameters(ParameterHandler &prm, const std::string &scene)
    {
      prm.declare_entry("Scene type", scene,
                        Patterns::Selection(SceneRegistry::instance().names_separated_by("|")),
                        "The scene to run: " + SceneRegistry::instance().names_separated_by(", ") + ".");
      prm.enter_subsection("Output");
      prm.declare_entry("Output directory", "results/" + scene, Patterns::FileName(),
                        "Folder for the results, relative to the current working directory; it is replaced "
                        "only when the run completes.");
      prm.leave_subsection();
    }

    struct ParsedRun
    {
      std::unique_ptr<ParameterHandler> prm;
      std::unique_ptr<Scene>            scene;
      std::string                       scene_name;
      std::string                       output_directory;
    };

    ParsedRun parse_parameter_file(const std::string &file)
    {
      AssertThrow(std::filesystem::is_regular_file(file),
                  ExcMessage("The parameter file <" + file + "> does not exist."));
      ParsedRun run;
      run.scene_name = read_scene_type(file);
      AssertThrow(!run.scene_name.empty(),
                  ExcMessage("The parameter file <" + file +
                             "> does not name a scene: add `set Scene type = NAME` at the top level. "
                             "Registered scenes: " +
                             SceneRegistry::instance().names_separated_by(", ") + "."));
      const SceneInfo &info = SceneRegistry::instance().get(run.scene_name);
      run.prm               = std::make_unique<ParameterHandler>();
      declare_common_parameters(*run.prm, run.scene_name);
      info.declare_parameters(*run.prm);
      set_current_parameter_directory(std::filesystem::path(file).parent_path().string());
      run.prm->parse_input(file, "", /*skip_undefined=*/false, /*assert_mandatory_entries_are_found=*/false);
      run.prm->enter_subsection("Output");
      run.output_directory = run.prm->get("Output directory");
      run.prm->leave_subsection();
      AssertThrow(!trim(run.output_directory).empty(), ExcMessage("The output directory must not be empty."));
      run.scene = info.create(*run.prm);
      run.scene->validate();
      return run;
    }

    int run_scene(const std::string &file, const std::string &output_override, MPI_Comm comm)
    {
      ParsedRun run = parse_parameter_file(file);
      if (!output_override.empty())
        {
          run.output_directory = output_override;
          run.prm->enter_subsection("Output");
          run.prm->set("Output directory", output_override);
          run.prm->leave_subsection();
        }
      OutputDirectory output(run.output_directory, comm);
      try
        {
          output.create();
          RunContext context(comm, output);
          context.pcout << "nlmech: scene <" << run.scene_name << "> from " << file << " on "
                        << Utilities::MPI::n_mpi_processes(comm) << " MPI rank(s) x "
                        << MultithreadInfo::n_threads() << " thread(s)" << std::endl;
          context.summary.add_string("scene", run.scene_name);
          context.summary.add_string("parameter_file", file);
          context.summary.add_number("mpi_ranks", Utilities::MPI::n_mpi_processes(comm));
          context.summary.add_number("threads_per_rank", MultithreadInfo::n_threads());
          run.scene->run(context);
          const bool partial       = !context.partial_reason.empty(),
                     checks_failed = !context.failed_checks.empty();
          context.summary.add_string("status", partial         ? "partial"
                                               : checks_failed ? "check_failed"
                                                               : "complete");
          if (partial)
            context.summary.add_string("partial_reason", context.partial_reason);
          if (checks_failed)
            context.summary.add_strings("failed_checks", context.failed_checks);

          if (context.is_root())
            {
              std::ostringstream resolved;
              run.prm->print_parameters(resolved, ParameterHandler::PRM);
              write_file_atomically(output.file("parameters.prm"), resolved.str());
            }
          context.timer.print_summary();
          if (context.is_root())
            {
              write_file_atomically(output.file("timing.txt"), context.timing_text.str());
              write_file_atomically(output.file("summary.json"), context.summary.to_string() + "\n");
            }
          output.commit();
          if (partial || checks_failed)
            {
              if (context.is_root())
                std::cerr << "nlmech: error: "
                          << (partial ? context.partial_reason + "; partial results in "
                                      : std::to_string(context.failed_checks.size()) +
                                            " of the run's own checks failed (see above); results in ")
                          << output.final_path() << "/" << std::endl;
              return 1;
            }
          context.pcout << "nlmech: results in " << output.final_path() << "/" << std::endl;
        }
      catch (...)
        {
          output.abandon();
          throw;
        }
      return 0;
    }
  } // namespace

  std::string read_scene_type(const std::string &parameter_file)
  {
    std::ifstream in(parameter_file);
    std::string   line;
    int           depth = 0;
    while (std::getline(in, line))
      {
        line = trim(line.substr(0, line.find('#')));
        if (line.rfind("subsection", 0) == 0)
          ++depth;
        else if (line == "end")
          --depth;
        else if (depth == 0 && line.rfind("set", 0) == 0)
          {
            const auto eq = line.find('=');
            if (eq != std::string::npos && trim(line.substr(3, eq - 3)) == "Scene type")
              return trim(line.substr(eq + 1));
          }
      }
    return "";
  }

  unsigned int take_thread_option(int &argc, char **argv)
  {
    unsigned int threads = numbers::invalid_unsigned_int;
    int          kept    = 1;
    for (int i = 1; i < argc; ++i)
      {
        const std::string arg = argv[i];
        if (arg != "--threads")
          {
            argv[kept++] = argv[i];
            continue;
          }
        AssertThrow(i + 1 < argc, ExcMessage("--threads needs a number of threads."));
        const std::string value = argv[++i];
        std::size_t       used  = 0;
        long              n     = 0;
        try
          {
            n = std::stol(value, &used);
          }
        catch (const std::exception &)
          {
            used = 0;
          }
        AssertThrow(used == value.size() && n >= 1 && n <= 4096,
                    ExcMessage("--threads expects a positive whole number, not <" + value + ">."));
        threads = static_cast<unsigned int>(n);
      }
    argc       = kept;
    argv[argc] = nullptr;
    return threads;
  }

  int run_command_line(int argc, char **argv, MPI_Comm comm)
  {
    const bool               root = Utilities::MPI::this_mpi_process(comm) == 0;
    std::vector<std::string> args(argv + 1, argv + argc);
    try
      {
        if (args.empty() || args[0] == "--help" || args[0] == "-h")
          {
            if (root)
              std::cout << usage;
            return args.empty() ? 1 : 0;
          }
        if (args[0] == "--list-scenes")
          {
            if (root)
              for (const auto &s : SceneRegistry::instance().scenes())
                std::cout << s.name << "\n    " << s.description << "\n";
            return 0;
          }
        if (args[0] == "--print-parameters")
          {
            AssertThrow(args.size() == 2, ExcMessage("--print-parameters needs a scene name."));
            const SceneInfo &info = SceneRegistry::instance().get(args[1]);
            ParameterHandler prm;
            declare_common_parameters(prm, info.name);
            info.declare_parameters(prm);
            if (root)
              prm.print_parameters(std::cout, ParameterHandler::PRM);
            return 0;
          }
        if (args[0] == "--validate")
          {
            AssertThrow(args.size() >= 2, ExcMessage("--validate needs at least one parameter file."));
            for (std::size_t i = 1; i < args.size(); ++i)
              {
                const ParsedRun run = parse_parameter_file(args[i]);
                if (root)
                  std::cout << args[i] << ": valid (scene " << run.scene_name << ")" << std::endl;
              }
            return 0;
          }
        AssertThrow(args[0].rfind("--", 0) != 0,
                    ExcMessage("Unknown option <" + args[0] + ">.\n" + std::string(usage)));
        std::string output_override;
        for (std::size_t i = 1; i < args.size(); ++i)
          if (args[i] == "--output-directory" && i + 1 < args.size())
            output_override = args[++i];
          else
            AssertThrow(false, ExcMessage("Unexpected argument <" + args[i] + ">.\n" + std::string(usage)));
        return run_scene(args[0], output_override, comm);
      }
    catch (...)
      {
        const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
        if (root || n_ranks > 1)
          std::cerr << "nlmech: error: "
                    << (n_ranks > 1 ? "[rank " + std::to_string(Utilities::MPI::this_mpi_process(comm)) + "] "
                                    : "")
                    << describe_current_exception() << std::endl;
        return 1;
      }
  }
} // namespace nlmech
