#pragma once
// spatial::lazy_snapshot<S> — an immutable derived copy of a container's data (for example
// the bvh's ray layout) that const queries build on first use, safe when many threads run
// const queries at once (batched queries) while nobody modifies the container.
//
//  * get(make): the snapshot; the first caller after a reset() builds it with make() under a
//    mutex, every later caller pays one acquire load (double-checked publication).
//  * reset(): drops the snapshot; called by the owner's modifiers (which, like every
//    non-const member, must not run concurrently with queries).
//  * Copies share the immutable snapshot (std::shared_ptr), so copying a container does not
//    copy its snapshot, and each copy drops its share on its own next modification.

#include <atomic>
#include <memory>
#include <mutex>
#include <utility>

namespace spatial {

template <class S>
class lazy_snapshot {
public:
    lazy_snapshot() = default;
    lazy_snapshot(const lazy_snapshot& o) : owner_(o.shared()) { ready_.store(owner_.get(), std::memory_order_release); }
    lazy_snapshot& operator=(const lazy_snapshot& o) {
        if (this != &o) {
            owner_ = o.shared();
            ready_.store(owner_.get(), std::memory_order_release);
        }
        return *this;
    }

    template <class Make>
    const S& get(Make&& make) const {
        if (const S* s = ready_.load(std::memory_order_acquire)) return *s;
        std::lock_guard<std::mutex> lock(mutex_);
        if (!owner_) {
            owner_ = std::make_shared<const S>(std::forward<Make>(make)());
            ready_.store(owner_.get(), std::memory_order_release);
        }
        return *owner_;
    }
    // The snapshot if built, else nullptr.
    const S* peek() const { return ready_.load(std::memory_order_acquire); }
    void reset() noexcept {
        if (ready_.load(std::memory_order_relaxed) == nullptr && !owner_) return;
        ready_.store(nullptr, std::memory_order_relaxed);
        owner_.reset();
    }
    void swap(lazy_snapshot& o) noexcept {
        std::swap(owner_, o.owner_);
        ready_.store(owner_.get(), std::memory_order_release);
        o.ready_.store(o.owner_.get(), std::memory_order_release);
    }

private:
    std::shared_ptr<const S> shared() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return owner_;
    }
    mutable std::mutex mutex_;
    mutable std::shared_ptr<const S> owner_;
    mutable std::atomic<const S*> ready_{nullptr};
};

}  // namespace spatial
