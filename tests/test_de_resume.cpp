// SPDX-License-Identifier: MIT
// Checkpoint and exact resume of DE-Path: a run stopped at any generation (suspended, or
// simply abandoned after a checkpoint, as a killed server would) and resumed from its
// checkpoint ends bit-identical to the uninterrupted run: same points, same energy, same
// generation and evaluation counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "depath/de/checkpoint.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/solve/solve.hpp"
#include "depath/util/error.hpp"
#include "path_checks.hpp"
#include "test_support.hpp"

namespace depath {
namespace {

JobSpec de_job(const std::string& strategy, int generations, bool refine) {
  JobSpec job;
  job.source = 0;
  job.target = 1400;
  job.method = Method::de;
  job.de.population = 12;
  job.de.generations = generations;
  job.de.strategy = strategy;
  job.seed = 7;
  job.refine = refine;
  job.threads = 2;
  return job;
}

// Every checkpoint the uninterrupted run offers (one per generation), resumed each in turn.
void check_resume_everywhere(const Mesh& mesh, const JobSpec& job, int stride) {
  std::map<int, std::string> checkpoints;
  SolveHooks hooks;
  hooks.checkpoint_due = [] { return true; };
  hooks.on_checkpoint = [&](const std::string& bytes) {
    checkpoints[decode_de_state(bytes).generation] = bytes;
  };
  const SolveResult full = solve(mesh, job, hooks);
  ASSERT_EQ(static_cast<int>(checkpoints.size()), job.de.generations);  // generations 0 .. G-1
  for (const auto& [generation, bytes] : checkpoints) {
    if (generation % stride != 0 && generation != job.de.generations - 1) continue;
    SolveHooks resume;
    resume.resume_from = bytes;
    EXPECT_TRUE(test::identical_results(full, solve(mesh, job, resume)))
        << job.de.strategy << " resumed after generation " << generation;
  }
}

// A run killed after generation `killed` resumes from its checkpoint after generation
// `checkpointed` (-1: none, it starts over), once with the journal of the generations
// between (what on_trial_energies reported) and once without: both bit-identical to the
// uninterrupted run. Returns the vertices the two resumes' marches made final (with, without).
std::pair<uint64_t, uint64_t> resume_with_journal(const Mesh& mesh, JobSpec job, int checkpointed,
                                                  int killed) {
  // Every generation's report carries the best path: the resumed run's must match (the
  // best of a replayed generation is decoded, not taken from an earlier agent).
  job.path_every = 1;
  std::map<int, std::vector<Vec3>> best_paths;
  std::string checkpoint;
  std::map<int, std::vector<double>> journal;
  SolveHooks hooks;
  hooks.checkpoint_due = [] { return true; };
  hooks.on_checkpoint = [&](const std::string& bytes) {
    if (decode_de_state(bytes).generation == checkpointed) checkpoint = bytes;
  };
  hooks.on_trial_energies = [&](int generation, std::span<const double> energies) {
    EXPECT_EQ(static_cast<int>(energies.size()), job.de.population);
    if (generation > checkpointed && generation <= killed)
      journal[generation].assign(energies.begin(), energies.end());
  };
  hooks.on_progress = [&](const Progress& p) {
    ASSERT_NE(p.best_path, nullptr);
    best_paths[p.generation] = path_positions(mesh, *p.best_path);
  };
  const SolveResult full = solve(mesh, job, hooks);
  EXPECT_TRUE(test::identical_results(full, solve(mesh, job))) << "checkpoints and a journal change nothing";
  EXPECT_EQ(static_cast<int>(journal.size()), killed - checkpointed);
  std::pair<uint64_t, uint64_t> marched;
  for (const bool with_journal : {true, false}) {
    SolveHooks resume;
    resume.resume_from = checkpoint;
    if (with_journal) {
      resume.recorded_trial_energies = journal;
      // An entry of another population size is ignored (taken, every trial would lose).
      resume.recorded_trial_energies[killed + 1].assign(job.de.population + 1, 1e300);
    }
    int generations = 0;
    resume.on_progress = [&](const Progress& p) {
      ++generations;
      ASSERT_NE(p.best_path, nullptr);
      EXPECT_EQ(path_positions(mesh, *p.best_path), best_paths[p.generation])
          << "best path after generation " << p.generation << (with_journal ? " with" : " without")
          << " a journal";
    };
    const uint64_t before = FastMarching::vertices_made_final();
    const SolveResult resumed = solve(mesh, job, resume);
    (with_journal ? marched.first : marched.second) = FastMarching::vertices_made_final() - before;
    EXPECT_TRUE(test::identical_results(full, resumed))
        << job.de.strategy << " resumed after generation " << checkpointed
        << (with_journal ? " with" : " without") << " a journal to " << killed;
    EXPECT_EQ(generations, job.de.generations - std::max(checkpointed, 0));
  }
  return marched;
}

TEST(DeResume, JournalSparesTheResumedRunItsDecodesAndChangesNothing) {
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  for (const std::string strategy : {"shade", "rand1bin"}) {
    const JobSpec job = de_job(strategy, 40, false);
    // Killed at generation 35, last checkpoint after 5: the resume replays 30 generations
    // from the journal and runs 5; without it, all 35 are decoded again.
    const auto [with, without] = resume_with_journal(mesh, job, 5, 35);
    EXPECT_LT(double(with), 0.4 * double(without)) << strategy << ": " << with << " vs " << without;
    // The whole run after the checkpoint journaled: nothing left but the best's decodes.
    const auto [all, none] = resume_with_journal(mesh, job, 10, 40);
    EXPECT_LT(double(all), 0.25 * double(none)) << strategy << ": " << all << " vs " << none;
    // Killed before its first checkpoint: it starts over, the journal from the initial agents on.
    const auto [fresh, again] = resume_with_journal(mesh, job, -1, 30);
    EXPECT_LT(double(fresh), 0.4 * double(again)) << strategy << ": " << fresh << " vs " << again;
  }
}

TEST(DeResume, RefinedRunWithAJournalDecodesEverything) {
  // Refinement needs every accepted trial's path: the journal is not used, the result is the same.
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  const auto [with, without] = resume_with_journal(mesh, de_job("shade", 20, true), 4, 16);
  EXPECT_EQ(with, without);
}

TEST(DeResume, ShadeResumesBitIdenticalFromEveryCheckpoint) {
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  check_resume_everywhere(mesh, de_job("shade", 40, false), 3);
}

TEST(DeResume, Rand1binResumesBitIdentical) {
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  check_resume_everywhere(mesh, de_job("rand1bin", 25, false), 4);
}

TEST(DeResume, RefinedResultResumesBitIdentical) {
  // Refinement starts from the final population's paths: a resume must rebuild them.
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  check_resume_everywhere(mesh, de_job("shade", 20, true), 7);
}

TEST(DeResume, SuspendCheckpointsAndStopsThenResumeFinishes) {
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  const JobSpec job = de_job("shade", 30, false);
  const SolveResult full = solve(mesh, job);
  std::string saved;
  int polls = 0;
  SolveHooks hooks;
  hooks.suspend = [&] { return ++polls > 12; };
  hooks.on_checkpoint = [&](const std::string& bytes) { saved = bytes; };
  const SolveResult stopped = solve(mesh, job, hooks);
  EXPECT_EQ(stopped.stop_reason, "suspended");
  EXPECT_EQ(stopped.generations, 12);
  ASSERT_FALSE(saved.empty());
  EXPECT_EQ(decode_de_state(saved).generation, 12);
  SolveHooks resume;
  resume.resume_from = saved;
  EXPECT_TRUE(test::identical_results(full, solve(mesh, job, resume))) << "resumed after a suspend";
}

TEST(DeResume, CheckpointSizeIsThePopulationAndArchive) {
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  const JobSpec job = de_job("shade", 10, false);
  std::string last;
  SolveHooks hooks;
  hooks.checkpoint_due = [] { return true; };
  hooks.on_checkpoint = [&](const std::string& bytes) { last = bytes; };
  solve(mesh, job, hooks);
  const DeState state = decode_de_state(last);
  const size_t n = static_cast<size_t>(mesh.num_vertices());
  EXPECT_EQ(state.agents.size(), 12 * n);
  // Population, at most N/2 archived parents, and a few hundred bytes of scalars.
  EXPECT_LE(last.size(), (12 + 6) * n * sizeof(double) + 1024);
  EXPECT_GE(last.size(), 12 * n * sizeof(double));
  EXPECT_EQ(encode_de_state(state), last);  // decoding and encoding round-trip exactly
}

TEST(DeResume, RefusesForeignOrDamagedCheckpoints) {
  const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  std::string saved;
  SolveHooks hooks;
  hooks.checkpoint_due = [] { return true; };
  hooks.on_checkpoint = [&](const std::string& bytes) { saved = bytes; };
  solve(mesh, de_job("shade", 3, false), hooks);
  SolveHooks other;
  other.resume_from = saved;
  JobSpec different = de_job("shade", 3, false);
  different.seed = 8;
  try {
    solve(mesh, different, other);
    FAIL() << "a checkpoint of another seed was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("does not belong"), std::string::npos) << e.what();
  }
  other.resume_from = saved.substr(0, saved.size() / 2);
  try {
    solve(mesh, de_job("shade", 3, false), other);
    FAIL() << "a truncated checkpoint was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a valid DE checkpoint"), std::string::npos) << e.what();
  }
  EXPECT_THROW(decode_de_state("garbage"), Error);
}

}  // namespace
}  // namespace depath
