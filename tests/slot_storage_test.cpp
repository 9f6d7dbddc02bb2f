// spatial::slot_storage (core/slot_storage.hpp), the element store behind every container:
// append, the bulk path of a build into new slots, stores a batch in order with its meta word,
// on one core or on every core alike, and a batch with a rejected value stores nothing and
// names the first rejected value; truncate undoes an append; free slots are left alone;
// permute renumbers the slots, each value keeping its meta word.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "spatial/core/slot_storage.hpp"
#include "test_support.hpp"

using namespace spatial;

namespace {

// Everything the storage holds, slot by slot: (occupied, value, meta).
struct slot_view {
    bool occupied;
    int value;
    slot_storage<int>::meta_type meta;
    friend bool operator==(const slot_view&, const slot_view&) = default;
};
template <class V>
std::vector<slot_view> view(const slot_storage<V>& s) {
    std::vector<slot_view> out;
    for (slot_index i = 0; i < s.capacity(); ++i)
        out.push_back({s.occupied(i), s.occupied(i) ? static_cast<int>(s.value(i)) : 0, s.meta(i)});
    return out;
}

// A value without a default constructor (append cannot make room first and copy after).
struct boxed {
    explicit boxed(int value) : v(value) {}
    int v;
    explicit operator int() const { return v; }
};

std::vector<int> counting(std::size_t n) {
    std::vector<int> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
    return out;
}

}  // namespace

TEST(slot_storage, append_stores_the_batch_in_order_on_one_core_and_on_every_core_alike) {
    const std::vector<int> batch = counting(100000);
    auto valid = [](int) { return true; };
    for (const bool parallel : {false, true}) {
        slot_storage<int> s;
        s.allocate(-1, 7);
        ASSERT_EQ(s.append(batch.begin(), batch.size(), 3, parallel, valid), batch.size());
        ASSERT_EQ(s.size(), batch.size() + 1);
        ASSERT_EQ(s.capacity(), batch.size() + 1);
        EXPECT_EQ(s.value(0), -1);
        EXPECT_EQ(s.meta(0), 7u);
        for (std::size_t i = 0; i < batch.size(); ++i) {
            ASSERT_EQ(s.value(static_cast<slot_index>(i + 1)), batch[i]) << "parallel " << parallel;
            ASSERT_EQ(s.meta(static_cast<slot_index>(i + 1)), 3u);
        }
    }
}

TEST(slot_storage, append_with_a_rejected_value_stores_nothing_and_returns_the_first_rejected) {
    const std::vector<int> batch = counting(100000);
    // Rejected values in different chunks, the later one met first by a concurrent copy.
    auto valid = [](int v) { return v != 30001 && v != 70002 && v != 99999; };
    for (const bool parallel : {false, true}) {
        slot_storage<int> s;
        for (int v : {10, 11, 12}) s.allocate(v, 1);
        s.release(1);  // a free slot: append reuses none
        const auto before = view(s);
        EXPECT_EQ(s.append(batch.begin(), batch.size(), 3, parallel, valid), 30001u) << "parallel " << parallel;
        EXPECT_EQ(view(s), before);
        EXPECT_EQ(s.size(), 2u);
        EXPECT_TRUE(s.reuses_a_slot());
        // The storage is usable as before: the free slot is reused by allocate, append appends.
        EXPECT_EQ(s.allocate(13, 1), 1u);
        const std::vector<int> two{20, 21};
        EXPECT_EQ(s.append(two.begin(), two.size(), 4, parallel, valid), 2u);
        EXPECT_EQ(s.value(3), 20);
        EXPECT_EQ(s.value(4), 21);
        EXPECT_EQ(s.meta(4), 4u);
    }
}

TEST(slot_storage, truncate_undoes_an_append) {
    const std::vector<int> batch = counting(5000);
    slot_storage<int> s;
    s.allocate(5, 1);
    const auto before = view(s);
    ASSERT_EQ(s.append(batch.begin(), batch.size(), 2, true, [](int) { return true; }), batch.size());
    s.truncate(1);
    EXPECT_EQ(view(s), before);
    EXPECT_EQ(s.size(), 1u);
}

TEST(slot_storage, append_of_values_without_a_default_constructor) {
    std::vector<boxed> batch;
    for (int i = 0; i < 1000; ++i) batch.emplace_back(i);
    slot_storage<boxed> s;
    s.allocate(boxed(-1), 1);
    EXPECT_EQ(s.append(batch.begin(), batch.size(), 2, true, [](const boxed& b) { return b.v != 500; }), 500u);
    EXPECT_EQ(s.capacity(), 1u);
    EXPECT_EQ(s.size(), 1u);
    EXPECT_EQ(s.append(batch.begin(), batch.size(), 2, true, [](const boxed&) { return true; }), 1000u);
    EXPECT_EQ(s.size(), 1001u);
    EXPECT_EQ(s.value(1000).v, 999);
    EXPECT_EQ(s.meta(1000), 2u);
}

// permute renumbers every slot (new slot i holds old slot order[i], with its meta word), on
// one core or on every core alike, for values with and without a default constructor.
TEST(slot_storage, permute_moves_each_value_with_its_meta_word) {
    const spatial_test::logged_seed seed(91);
    std::mt19937_64 rng(seed);
    const std::vector<int> batch = counting(50000);
    std::vector<slot_index> order(batch.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<slot_index>(i);
    std::shuffle(order.begin(), order.end(), rng);
    for (const bool parallel : {false, true}) {
        slot_storage<int> s;
        ASSERT_EQ(s.append(batch.begin(), batch.size(), 0, false, [](int) { return true; }), batch.size());
        for (slot_index i = 0; i < s.capacity(); ++i) s.set_meta(i, 3 * i + 1);
        s.permute(order, parallel);
        ASSERT_EQ(s.size(), batch.size());
        ASSERT_EQ(s.capacity(), batch.size());
        for (slot_index i = 0; i < s.capacity(); ++i) {
            ASSERT_EQ(s.value(i), batch[order[i]]) << "slot " << i << ", parallel " << parallel;
            ASSERT_EQ(s.meta(i), 3 * order[i] + 1) << "slot " << i << ", parallel " << parallel;
        }
    }
    std::vector<boxed> boxes;
    for (int i = 0; i < 1000; ++i) boxes.emplace_back(i);
    slot_storage<boxed> b;
    ASSERT_EQ(b.append(boxes.begin(), boxes.size(), 5, true, [](const boxed&) { return true; }), boxes.size());
    std::vector<slot_index> reversed(boxes.size());
    for (std::size_t i = 0; i < reversed.size(); ++i) reversed[i] = static_cast<slot_index>(boxes.size() - 1 - i);
    b.permute(reversed, true);
    for (slot_index i = 0; i < b.capacity(); ++i) {
        ASSERT_EQ(b.value(i).v, static_cast<int>(boxes.size() - 1 - i));
        ASSERT_EQ(b.meta(i), 5u);
    }
}
