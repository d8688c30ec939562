// A trivial adapter for measuring the protocol's throughput from Node: the n/p-vertex test
// (Assarsson & Moller 2000, section 3.1) on our planes as given, in plain JS (double arithmetic on
// the float inputs), for AABBs. Per plane: the p-vertex (the corner farthest along n) below the
// plane is outside; the n-vertex (the nearest) below it means not inside.
import { serve } from './protocol.mjs';

serve([
  {
    hello: {
      name: 'node-pn-vertex',
      origin: 'user',
      claim: 'conservative',
      tolerance: 1e-6,
      volumes: ['aabb'],
      three_way: true,
      description: 'n/p-vertex test in plain JS, for measuring the protocol from Node',
      source: 'Assarsson & Moller 2000, section 3.1 (examples/engines/node/trivial.mjs)',
      touching: 'kept: outside only when the p-vertex value is < 0',
    },
    frame(planes) {
      return {
        prepare: (v) => v,
        classify({ min, max }) {
          let inside = true;
          for (const [a, b, c, d] of planes) {
            const p = a * (a >= 0 ? max[0] : min[0]) + b * (b >= 0 ? max[1] : min[1]) + c * (c >= 0 ? max[2] : min[2]) + d;
            if (p < 0) return 'outside';
            const n = a * (a >= 0 ? min[0] : max[0]) + b * (b >= 0 ? min[1] : max[1]) + c * (c >= 0 ? min[2] : max[2]) + d;
            if (n < 0) inside = false;
          }
          return inside ? 'inside' : 'intersecting';
        },
      };
    },
  },
]);
