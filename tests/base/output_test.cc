// Tests source/base: atomic files, the JSON summary writer, progress estimates and slope fits.
#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/mesh_study.h>
#include <nlmech/base/progress.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace nlmech;
namespace fs = std::filesystem;

TEST(AtomicFile, NothingAppearsUntilCommit)
{
  const fs::path dir = fs::temp_directory_path() / "nlmech_atomic_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "result.txt").string();
  {
    AtomicFile file(path);
    file.stream() << "half";
    EXPECT_FALSE(fs::exists(path));
  } // destroyed without commit: no file, no temporary
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir));
  write_file_atomically(path, "complete");
  std::ifstream in(path);
  std::string   content;
  in >> content;
  EXPECT_EQ(content, "complete");
  fs::remove_all(dir);
}

TEST(OutputDirectory, StagedUntilCommitAndRemovedOnAbandon)
{
  const fs::path final_dir = fs::temp_directory_path() / "nlmech_output_test";
  fs::remove_all(final_dir);
  OutputDirectory output(final_dir.string(), MPI_COMM_SELF);
  output.create();
  write_file_atomically(output.file("a.txt"), "x");
  EXPECT_FALSE(fs::exists(final_dir));
  output.commit();
  EXPECT_TRUE(fs::exists(final_dir / "a.txt"));
  OutputDirectory second(final_dir.string(), MPI_COMM_SELF);
  second.create();
  second.abandon();
  EXPECT_TRUE(fs::exists(final_dir / "a.txt")); // the previous results stay
  EXPECT_FALSE(fs::exists(final_dir.string() + ".incomplete"));
  fs::remove_all(final_dir);
}

TEST(Json, FiguresWithUnitsAndNoNaN)
{
  JsonObject inner;
  inner.add_figure("length", 1.5, "m");
  JsonObject outer;
  outer.add_string("scene", "a \"quoted\" name");
  outer.add_object("nested", inner);
  outer.add_numbers("list", {1, 2.5});
  const std::string text = outer.to_string();
  EXPECT_NE(text.find("\"length\": {\"value\": 1.5, \"unit\": \"m\"}"), std::string::npos) << text;
  EXPECT_NE(text.find("a \\\"quoted\\\" name"), std::string::npos);
  JsonObject bad;
  EXPECT_THROW(bad.add_figure("x", std::nan(""), "m"), dealii::ExceptionBase);
  EXPECT_THROW(bad.add_number("y", INFINITY), dealii::ExceptionBase);
}

TEST(MeshStudy, FittedOrders)
{
  MeshStudyTable table("error");
  for (unsigned int level = 0; level < 4; ++level)
    {
      MeshStudyTable::Row row;
      row.level        = level;
      row.element_size = std::pow(0.5, level);
      row.n_dofs       = 1000ull << (3 * level); // DOFs ~ h^-3
      row.error        = 0.1 * std::pow(row.element_size, 2);
      table.add(row);
    }
  EXPECT_NEAR(table.fitted_order_in_h(), 2.0, 1e-12);
  EXPECT_NEAR(table.fitted_order_in_dofs(3), 2.0, 1e-12);
  EXPECT_NE(table.to_csv().find("level,element_size_m,n_cells,n_dofs,error,wall_time_s"), std::string::npos);
}

TEST(Progress, TimeLeftExtrapolatesFromWorkDone)
{
  std::ostringstream out;
  ProgressReporter   progress("test", 10.0, MPI_COMM_SELF, out);
  EXPECT_LT(progress.estimated_seconds_left(0), 0);
  const double elapsed = progress.elapsed_seconds();
  EXPECT_LE(progress.estimated_seconds_left(5.0), 2 * elapsed + 1.0);
  progress.report(5.0, "half");
  EXPECT_NE(out.str().find("50.0% done"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("left (half)"), std::string::npos) << out.str();
}
