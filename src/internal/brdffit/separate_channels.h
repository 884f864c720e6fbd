// Derivatives one per parameter for models whose colour channels are separate.
//
// A model declares kSeparateChannels = true (with kNumParameters, its number of parameters) when
// channel c of its shade depends on its scalar parameters and on component c of each colour
// only: no luminance, no maximum over channels. Each derivative slot of the Jets then stands
// for a parameter rather than a value: a colour's three components share one slot, and channel
// c of the shade's derivative in that slot is its derivative with respect to component c (the
// other two do not enter channel c). sgd's eleven colours are differentiated with Jet<11>
// instead of Jet<33>, openpbr's with Jet<6> instead of Jet<10>: the arithmetic of every Jet
// operation shrinks in proportion. AllModels.AutodiffGradientsMatchCentralDifferences catches a
// model that declares separate channels without having them.
#pragma once

#include <type_traits>
#include <vector>

#include "brdffit/param.h"

namespace brdffit {

template <class M, class = void>
struct SeparateChannels : std::false_type {};
template <class M>
struct SeparateChannels<M, std::void_t<decltype(M::kSeparateChannels)>> : std::bool_constant<M::kSeparateChannels> {};

// Where each value's derivative is carried when the channels are separate.
struct ParameterSlots {
  std::vector<int> slot_of_value;     // the value's parameter
  std::vector<int> channel_of_value;  // its colour channel, -1 for a scalar
  std::vector<int> offset, channels;  // per parameter (slot)

  explicit ParameterSlots(const std::vector<ParamSpec>& params) {
    for (size_t p = 0; p < params.size(); ++p) {
      offset.push_back(static_cast<int>(slot_of_value.size()));
      channels.push_back(params[p].channels);
      for (int c = 0; c < params[p].channels; ++c) {
        slot_of_value.push_back(static_cast<int>(p));
        channel_of_value.push_back(params[p].channels == 1 ? -1 : c);
      }
    }
  }
  int slots() const { return static_cast<int>(offset.size()); }
  // The value whose derivative slot `slot` carries in channel c of the shade.
  int value(int slot, int c) const { return offset[slot] + (channels[slot] == 1 ? 0 : c); }
  // Whether value i enters channel c of the shade at all.
  bool enters(int i, int c) const { return channel_of_value[i] < 0 || channel_of_value[i] == c; }
};

// The slots of model M, computed once.
template <class M>
const ParameterSlots& parameter_slots() {
  static const ParameterSlots slots(M::parameters());
  return slots;
}

}  // namespace brdffit
