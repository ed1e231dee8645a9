// The docs' examples run as written (docs/cli.md, docs/sweeps.md): every command
// succeeds and the files it names are there. The main job's files are read against the
// docs in Cli.DemoQuickEndToEnd (docs_check.hpp).
#include <gtest/gtest.h>

#include "docs_check.hpp"

TEST(Docs, CliExamplesRun) { EXPECT_GE(atmosh::test::run_doc_examples("cli.md"), 15); }

TEST(Docs, SweepExampleRuns) { EXPECT_GE(atmosh::test::run_doc_examples("sweeps.md"), 4); }
