"""The event queue: particles' event times in blocks of QUEUE_BLOCK and a tournament tree over the blocks."""

from __future__ import annotations

import math

# no EDMD kernel allocates or returns an array: all of them borrow, without reference counting
from ..._jit import borrowing_inline_kernel as inline_kernel
from ..._jit import borrowing_kernel as kernel
from .._memory import prefetch
from .layout import QUEUE_BLOCK, TREE_LEVELS_PREFETCHED


@inline_kernel
def tree_update(leaf, tree, time, winner, leaves):
    """Give ``leaf`` (a block) a new earliest event and replay its matches up the tournament tree.

    ``tree[node] = (time, particle)`` of the winner below ``node`` (the
    particle index stored as a float, exact below 2^53), so both sit in one
    cache line with the sibling's; the climb stops where nothing changes.
    The winner so far rides up in registers and meets one sibling per level
    (the left one wins ties).
    """
    node = leaves + leaf
    tree[node, 0] = time
    tree[node, 1] = winner
    best_time = time
    best_id = winner
    while node > 1:
        # loads first, then selects (cmov): which side wins is a coin toss, a poor bet for a branch
        sibling_time = tree[node ^ 1, 0]
        sibling_id = tree[node ^ 1, 1]
        sibling_wins = (sibling_time < best_time) | ((sibling_time == best_time) & (node & 1 == 1))
        best_id = sibling_id if sibling_wins else best_id
        best_time = min(sibling_time, best_time)
        node >>= 1
        if tree[node, 0] == best_time and tree[node, 1] == best_id:
            return
        tree[node, 0] = best_time
        tree[node, 1] = best_id


@inline_kernel
def _block_first(block, queue):
    """Earliest event of a block of the queue: (time, particle); the lowest index wins ties."""
    first = block * QUEUE_BLOCK
    best_time = queue[first]
    best = first
    for k in range(first + 1, first + QUEUE_BLOCK):
        earlier = queue[k] < best_time
        best = k if earlier else best
        best_time = queue[k] if earlier else best_time
    return best_time, best


@inline_kernel
def queue_update(i, time, queue, tree, leaves):
    """Give particle i the event time ``time`` in the queue.

    The block's entry in the tree changes only if i was its first particle
    or now comes first; otherwise the update ends here, without a scan.
    """
    queue[i] = time
    block = i // QUEUE_BLOCK
    node = leaves + block
    block_time = tree[node, 0]
    block_first = int(tree[node, 1])
    if block_first != i:
        if time > block_time or (time == block_time and i > block_first):
            return
        tree_update(block, tree, time, float(i), leaves)
        return
    if time <= block_time:
        tree_update(block, tree, time, float(i), leaves)
        return
    best_time, best = _block_first(block, queue)
    tree_update(block, tree, best_time, float(best), leaves)


@inline_kernel
def prefetch_queue_entry(i, queue, tree, leaves):
    """Start loading particle i's queue entry and the lowest nodes of its block's path up the tree."""
    prefetch(queue, i)
    node = leaves + i // QUEUE_BLOCK
    for _ in range(TREE_LEVELS_PREFETCHED):
        prefetch(tree, node)
        node >>= 1


@inline_kernel
def likely_next(i, tree, leaves):
    """The particle of the second-earliest event, a guess good enough for prefetching.

    The runner-up of the tournament is the best of the siblings along the
    winner i's path; the block and the lowest levels (cold in cache) are
    skipped, so the guess misses if the runner-up lies among i's nearest
    32 particles. Returns -1 if there is no guess.
    """
    node = (leaves + i // QUEUE_BLOCK) >> 2 if leaves >= 8 else leaves + i // QUEUE_BLOCK
    best_time = math.inf
    best = -1.0
    while node > 1:
        sibling_time = tree[node ^ 1, 0]
        sibling_id = tree[node ^ 1, 1]
        best = sibling_id if sibling_time < best_time else best
        best_time = min(sibling_time, best_time)
        node >>= 1
    return int(best)


@kernel
def tree_build(tree, queue, leaves):
    """Fill the tree over the queue's blocks (queue padded with inf to whole blocks)."""
    blocks = queue.shape[0] // QUEUE_BLOCK
    for leaf in range(leaves):
        if leaf < blocks:
            best_time, best = _block_first(leaf, queue)
        else:
            best_time, best = math.inf, leaf * QUEUE_BLOCK
        tree[leaves + leaf, 0] = best_time
        tree[leaves + leaf, 1] = best
    for node in range(leaves - 1, 0, -1):
        left = 2 * node
        winner = left if tree[left, 0] <= tree[left + 1, 0] else left + 1
        tree[node, 0] = tree[winner, 0]
        tree[node, 1] = tree[winner, 1]
