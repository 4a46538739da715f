// The single-ray walks of `accel/bvh/mod.rs` over the same 4-wide nodes:
// nearest hit (children nearest first, boxes beyond the best hit skipped)
// and any hit (children in slot order), with the infinite planes tested
// beside the tree as `Tracer::trace` does.
//
// const BVH_STACK: u32 (prepended): three entries per level of the tree
// uploaded, so the stack cannot overflow.

struct Entry {
    child: u32,
    count: u32,
    t: f32,
}

// `Node4::hit` for one slot: where the ray enters the box, or infinity.
fn enter_box(node: Node, slot: u32, q: Query, t_max: f32) -> f32 {
    let lo = vec3<f32>(node.lo[0][slot], node.lo[1][slot], node.lo[2][slot]);
    let hi = vec3<f32>(node.hi[0][slot], node.hi[1][slot], node.hi[2][slot]);
    let neg = q.inv < vec3<f32>(0.0);
    let near = select(lo, hi, neg);
    let far = select(hi, lo, neg);
    let tn = (near - q.o) * q.inv;
    let tf = (far - q.o) * q.inv;
    let t_near = max(max(max(tn.x, tn.y), tn.z), q.t_min);
    let t_far = min(min(min(tf.x, tf.y), tf.z) * bitcast<f32>(SLAB_WIDEN_BITS), t_max);
    if t_near <= t_far {
        return t_near;
    }
    return infinity();
}

// `Node4::entry`: child `slot` of `node` as a stack entry.
fn child_entry(node: Node, slot: u32, t: f32) -> Entry {
    return Entry(node.child[slot], node.count[slot], t);
}

// The next entry off the stack into `e`; false when the stack is empty
// (the walk is over).
fn pop(stack: ptr<function, array<Entry, BVH_STACK>>, sp: ptr<function, u32>, e: ptr<function, Entry>) -> bool {
    if *sp == 0u {
        return false;
    }
    *sp -= 1u;
    *e = (*stack)[*sp];
    return true;
}

// `test_prim` for the nearest hit: ties go to the lower id, so the image
// does not depend on the order leaves are visited.
fn test_nearest(id: u32, q: Query, best: ptr<function, Hit>, t_max: f32) {
    var limit = t_max;
    if (*best).prim != UNUSED {
        limit = bitcast<f32>(bitcast<u32>((*best).t) + 1u);
    }
    let h = intersect(id, q, limit);
    if h.t < infinity() && ((*best).prim == UNUSED || h.t < (*best).t || (h.t == (*best).t && h.prim < (*best).prim)) {
        *best = h;
    }
}

fn nearest(q: Query, t_max: f32) -> Hit {
    var stack: array<Entry, BVH_STACK>;
    var best = no_hit();
    if P.ids.z > 0u {
        var box_limit = t_max * bitcast<f32>(ENTRY_SLACK_BITS);
        var e = Entry(0u, 0u, q.t_min);
        var sp = 0u;
        loop {
            var descend = false;
            if e.t <= box_limit {
                if e.count > 0u {
                    for (var i = e.child; i < e.child + e.count; i++) {
                        test_nearest(leaf_ids[i], q, &best, t_max);
                    }
                    if best.prim != UNUSED {
                        box_limit = best.t * bitcast<f32>(ENTRY_SLACK_BITS);
                    }
                } else {
                    let node = nodes[e.child];
                    // The entered children, sorted by entry distance,
                    // farthest first.
                    var ts: array<f32, 4>;
                    var slots: array<u32, 4>;
                    var n = 0u;
                    for (var slot = 0u; slot < 4u; slot++) {
                        var t = infinity();
                        if node.count[slot] != UNUSED {
                            t = enter_box(node, slot, q, box_limit);
                        }
                        if t != infinity() {
                            var k = n;
                            while k > 0u && ts[k - 1u] < t {
                                ts[k] = ts[k - 1u];
                                slots[k] = slots[k - 1u];
                                k--;
                            }
                            ts[k] = t;
                            slots[k] = slot;
                            n++;
                        }
                    }
                    if n > 0u {
                        for (var i = 0u; i + 1u < n; i++) {
                            stack[sp] = child_entry(node, slots[i], ts[i]);
                            sp++;
                        }
                        e = child_entry(node, slots[n - 1u], ts[n - 1u]);
                        descend = true;
                    }
                }
            }
            if !descend && !pop(&stack, &sp, &e) {
                break;
            }
        }
    }
    for (var id = P.ids.z; id < P.ids.w; id++) {
        test_nearest(id, q, &best, t_max);
    }
    return best;
}

// Whether anything lies within (q.t_min, t_max): planes first, then the
// tree in slot order, stopping at the first hit.
fn occluded(q: Query, t_max: f32) -> bool {
    for (var id = P.ids.z; id < P.ids.w; id++) {
        if intersect(id, q, t_max).t < infinity() {
            return true;
        }
    }
    if P.ids.z == 0u {
        return false;
    }
    let box_limit = t_max * bitcast<f32>(ENTRY_SLACK_BITS);
    var stack: array<Entry, BVH_STACK>;
    var e = Entry(0u, 0u, q.t_min);
    var sp = 0u;
    loop {
        var descend = false;
        if e.count > 0u {
            for (var i = e.child; i < e.child + e.count; i++) {
                if intersect(leaf_ids[i], q, t_max).t < infinity() {
                    return true;
                }
            }
        } else {
            let node = nodes[e.child];
            var next = UNUSED;
            for (var slot = 0u; slot < 4u; slot++) {
                if node.count[slot] != UNUSED && enter_box(node, slot, q, box_limit) != infinity() {
                    if next != UNUSED {
                        stack[sp] = child_entry(node, next, 0.0);
                        sp++;
                    }
                    next = slot;
                }
            }
            if next != UNUSED {
                e = child_entry(node, next, 0.0);
                descend = true;
            }
        }
        if !descend && !pop(&stack, &sp, &e) {
            break;
        }
    }
    return false;
}
