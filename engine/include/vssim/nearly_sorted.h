// Sorting an order kept from the last call (the broad phase's robots along
// x, the planner's bodies along x): bodies move little between calls, so
// the order is nearly sorted already and an insertion sort takes about one
// pass, where a fresh sort would take n log n comparisons every time.
#pragma once

#include <cstddef>
#include <vector>

namespace vssim {

// Sorts `items` by `less` (a strict weak order), stable: linear time when
// each item is within a few places of where it belongs.
template <class T, class Less>
void sortNearlySorted(std::vector<T>& items, const Less& less) {
    for (std::size_t k = 1; k < items.size(); ++k) {
        const T item = items[k];
        std::size_t j = k;
        for (; j > 0 && less(item, items[j - 1]); --j) items[j] = items[j - 1];
        items[j] = item;
    }
}

}  // namespace vssim
