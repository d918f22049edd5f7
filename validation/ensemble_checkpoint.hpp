#pragma once
// An ensemble kept in a file as it goes, so that a long one (a thousand 2-D impacts take ten minutes to
// an hour) stopped at any point continues where it stood. Run i depends on i alone (ensemble.hpp), so a
// row found in the file is the row the run would compute: the continued ensemble ends with the same table
// as one that never stopped, on any number of ranks, and may ask for more runs than the first did.
#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ensemble.hpp"

namespace grainlab::validation {

struct EnsembleCheckpoint {
  std::string path;         // empty: no file, the ensemble is run as it is
  std::string what;         // what the file holds, for messages ("impact checkpoint")
  std::string fingerprint;  // everything that decides the rows; a file written with another is refused
  std::string mismatch;     // what to pass instead, when it is
  std::string option = "--checkpoint";  // the option that named the file, for messages
  double seconds_between_writes = 30;   // wall time; the last round is always written
};

// The rows of runs 0..runs-1 (each `width` numbers, as run_ensemble): those in the checkpoint file as
// they are, the rest computed in rounds of a few runs per rank, and the file rewritten atomically by rank
// 0 after a round once `seconds_between_writes` have passed since the last write, and after the last.
std::vector<std::vector<double>> run_checkpointed_ensemble(
    std::size_t runs, std::size_t width, const std::function<std::vector<double>(std::size_t)>& run,
    const EnsembleCheckpoint& checkpoint, const EnsembleProgress& progress = {});

// The file's rows by run index (none if the file does not exist). Throws InputError (naming the file and
// checkpoint.option) if it is damaged, not an ensemble checkpoint, or written for another fingerprint,
// grainlab version or row width.
std::map<std::size_t, std::vector<double>> read_ensemble_checkpoint(const EnsembleCheckpoint& checkpoint,
                                                                    std::size_t width);
// Writes them atomically: each row without its trailing zeros (an impact's unused ejecta slots).
void write_ensemble_checkpoint(const EnsembleCheckpoint& checkpoint, std::size_t width,
                               const std::map<std::size_t, std::vector<double>>& rows);

}  // namespace grainlab::validation
