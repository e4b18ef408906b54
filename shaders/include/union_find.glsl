// The union-find of the connected-component kernels (region_merge.comp, membrane_merge.comp):
// find() follows the parents to the root; unite() links the larger root under the smaller by
// atomicMin and retries where another invocation linked it first (Playne and Hawick, "A New
// Algorithm for Parallel Connected-Component Labelling on GPUs", 2018), so a component's root is
// its least element. Include after declaring `coherent volatile buffer ... { uint parent[]; }`.

uint find(uint i) {
  uint p = parent[i];
  while (p != i) {
    i = p;
    p = parent[i];
  }
  return i;
}

void unite(uint a, uint b) {
  for (;;) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) {
      const uint t = a;
      a = b;
      b = t;
    }
    const uint old = atomicMin(parent[a], b);
    if (old == a) return;
    a = old;
  }
}
