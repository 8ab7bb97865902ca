// What the MPI ranks of one training share (docs/mpi.md): rank 0 reads and writes RUN_DIR; the others start from
// its config and its networks' state, so that every rank steps the same parameters whatever its device or its
// view of the file system — a config chosen for rank 0's device (batch, width) holds for all.
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "radiosity/trainer.hpp"

namespace clr::radiosity {
namespace {

// The tensors Network::add_tensors writes, in its order, with the sizes a network of this config holds.
void share_network_state(const distributed::Communicator& ranks, nn::Network& net) {
  nn::Checkpoint c;
  if (ranks.rank() == 0) c = net.checkpoint();
  std::uint64_t step = c.step;
  ranks.broadcast(std::span<std::uint64_t>(&step, 1));
  if (ranks.rank() != 0) {
    // A network of this config built on this rank has the shapes rank 0's tensors have.
    c = net.checkpoint();
    c.step = step;
  }
  for (auto& [name, values] : c.tensors) ranks.broadcast(std::span<float>(values));
  if (ranks.rank() != 0) net.restore(c, "rank 0's state", "");
}

}  // namespace

void Trainer::share_rank0_state() {
  const distributed::Communicator& ranks = exchange_.communicator();
  if (!ranks.distributed()) return;
  std::string text = writes_run_dir() ? nlohmann::json(config_).dump() : std::string();
  ranks.broadcast(text);
  if (!writes_run_dir()) {
    config_ = parse_train_config(parse_json(text, "rank 0's config"));
    network_ = std::make_unique<nn::Network>(*ctx_, nn::network_config_from_json(config_.network));
    if (config_.average_steps > 0) network_->start_average();  // so that its tensors are rank 0's
    if (config_.guided()) guide_ = std::make_unique<nn::Network>(*ctx_, nn::network_config_from_json(config_.guide));
  }
  if (std::size_t(config_.batch) < std::size_t(ranks.size()))
    throw InputError("--batch " + std::to_string(config_.batch) + " is smaller than the " +
                     std::to_string(ranks.size()) + " ranks sharing it");
  share_network_state(ranks, *network_);
  if (guide_) share_network_state(ranks, *guide_);
  if (lagged()) {
    // The I-Module before its last update, where rank 0 resumed with it: every rank draws the same lobes from it.
    std::uint64_t has_before = guide_before_ ? 1 : 0;
    ranks.broadcast(std::span<std::uint64_t>(&has_before, 1));
    if (has_before) {
      if (!guide_before_) guide_before_ = std::make_unique<nn::Network>(*ctx_, guide_->config());
      share_network_state(ranks, *guide_before_);
      before_step_ = guide_->steps() - 1;
    }
  }
}

void Trainer::check_ranks_agree(std::uint64_t step) const {
  exchange_.check_same_parameters(*network_, "N-Module", step);
  if (guide_) exchange_.check_same_parameters(*guide_, "I-Module", step);
}

}  // namespace clr::radiosity
