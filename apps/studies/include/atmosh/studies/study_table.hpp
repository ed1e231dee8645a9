// atmosh/studies/study_table.hpp — what an error-against-run-time study returns: the
// table's spec, its rows and provenance, ready for io::write_study (STEM.csv, STEM.png).
#pragma once

#include <vector>

#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"

namespace atmosh::studies {

struct StudyTable {
  io::StudySpec spec;
  std::vector<io::StudyRow> rows;
  io::Provenance provenance;
};

}  // namespace atmosh::studies
