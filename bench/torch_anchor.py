#!/usr/bin/env python3
"""PyTorch CPU anchor for bench_nn: the same N-Module training step as clradiosity's (docs/design.md §6).

One step = forward of B training points through hash grid + SH(w_o) + SH(n) + albedo -> 4x512 ReLU -> 3, abs;
an inference forward of 4·B incident points without gradient; relative L2 loss against a fixed target;
backward; Adam over every parameter (PyTorch's dense Adam, as a straightforward implementation would).
Prints one JSON object: {"step_ms": median over the timed steps with the faster thread count, "threads": that
count, "step_ms_by_threads": {count: ms}}.
"""
import argparse
import json
import os
import time

import torch

PRIMES = (1, 2654435761, 805459861)


def levels_of(levels, log2_table, base, growth):
    T = 1 << log2_table
    out, offset = [], 0
    for l in range(levels):
        res = int(base * growth**l)  # floor, as the C++ side (positive values)
        dense = (res + 1) ** 3 <= T
        entries = (res + 1) ** 3 if dense else T
        out.append((res, dense, offset, entries))
        offset += entries
    return out, offset


class HashGrid(torch.nn.Module):
    def __init__(self, levels, features, log2_table, base, growth):
        super().__init__()
        self.levels, total = levels_of(levels, log2_table, base, growth)
        self.table = torch.nn.Parameter(torch.empty(total, features).uniform_(-1e-4, 1e-4))

    def forward(self, x):  # x in [0, 1]^3
        # All levels and corners in one gather (and so one scatter-add in backward): the fastest plain-PyTorch
        # formulation we know, so the anchor is not handicapped by 96 separate indexing ops.
        idx, wts = [], []
        for res, dense, offset, entries in self.levels:
            pos = x * res
            c = torch.clamp(torch.floor(pos), max=res - 1)
            t = pos - c
            ci = c.long()
            for corner in range(8):
                d = [(corner >> i) & 1 for i in range(3)]
                v = [ci[:, i] + d[i] for i in range(3)]
                w = 1
                for i in range(3):
                    w = w * (t[:, i] if d[i] else 1 - t[:, i])
                if dense:
                    side = res + 1
                    e = v[0] + side * (v[1] + side * v[2])
                else:
                    e = (v[0] * PRIMES[0] ^ v[1] * PRIMES[1] ^ v[2] * PRIMES[2]) & (entries - 1)
                idx.append(e + offset)
                wts.append(w)
        L = len(self.levels)
        idx = torch.stack(idx, dim=1)  # [B, L·8]
        wts = torch.stack(wts, dim=1)
        f = self.table[idx] * wts[:, :, None]  # [B, L·8, F]
        return f.view(x.shape[0], L, 8, -1).sum(dim=2).reshape(x.shape[0], -1)


def sh16(d):
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    xy, xz, yz, x2, y2, z2 = x * y, x * z, y * z, x * x, y * y, z * z
    return torch.stack([
        torch.full_like(x, 0.28209479177387814), -0.48860251190291987 * y, 0.48860251190291987 * z,
        -0.48860251190291987 * x, 1.0925484305920792 * xy, -1.0925484305920792 * yz,
        0.94617469575755997 * z2 - 0.31539156525251999, -1.0925484305920792 * xz, 0.54627421529603959 * (x2 - y2),
        0.59004358992664352 * y * (-3.0 * x2 + y2), 2.8906114426405538 * xy * z,
        0.45704579946446572 * y * (1.0 - 5.0 * z2), 0.3731763325901154 * z * (5.0 * z2 - 3.0),
        0.45704579946446572 * x * (1.0 - 5.0 * z2), 1.4453057213202769 * z * (x2 - y2),
        0.59004358992664352 * x * (-x2 + 3.0 * y2)], dim=1)


class NModule(torch.nn.Module):
    def __init__(self, a):
        super().__init__()
        self.grid = HashGrid(a.levels, a.features, a.log2_table, a.base, a.growth)
        layers, fan_in = [], a.levels * a.features + 16 + 16 + 3
        for _ in range(a.hidden):
            layers += [torch.nn.Linear(fan_in, a.width), torch.nn.ReLU()]
            fan_in = a.width
        layers.append(torch.nn.Linear(fan_in, 3))
        self.mlp = torch.nn.Sequential(*layers)

    def forward(self, raw):  # raw: [rows, 13] = x, w_o, n, albedo, roughness; x already in [0, 1]^3
        enc = torch.cat([self.grid(raw[:, 0:3]), sh16(raw[:, 3:6]), sh16(raw[:, 6:9]), raw[:, 9:12]], dim=1)
        return self.mlp(enc).abs()


def random_raw(rows, gen):
    raw = torch.rand(rows, 13, generator=gen)
    for s in (3, 6):
        d = torch.randn(rows, 3, generator=gen)
        raw[:, s:s + 3] = d / d.norm(dim=1, keepdim=True)
    return raw


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--batch", type=int, default=16384)
    p.add_argument("--incident", type=int, default=4)
    p.add_argument("--levels", type=int, default=12)
    p.add_argument("--features", type=int, default=2)
    p.add_argument("--log2-table", type=int, default=18)
    p.add_argument("--base", type=int, default=16)
    p.add_argument("--growth", type=float, default=1.5)
    p.add_argument("--width", type=int, default=512)
    p.add_argument("--hidden", type=int, default=4)
    p.add_argument("--steps", type=int, default=5)
    a = p.parse_args()
    # Our OpenCL device uses every core. PyTorch's OpenMP threads spin-wait, which on a shared, busy machine can
    # make every small op hundreds of times slower than one thread; so the anchor is the faster of all cores
    # and one thread, measured in the same run.
    results = {}
    for threads in sorted({os.cpu_count() or 1, 1}, reverse=True):
        torch.set_num_threads(threads)
        results[threads] = time_step(a)
    best = min(results, key=results.get)
    print(json.dumps({"step_ms": results[best], "threads": best,
                      "step_ms_by_threads": {str(t): ms for t, ms in results.items()}}))


def time_step(a):
    gen = torch.Generator().manual_seed(1)
    torch.manual_seed(1)
    net = NModule(a)
    opt = torch.optim.Adam(net.parameters(), lr=5e-3)
    raw = random_raw(a.batch, gen)
    incident = random_raw(a.batch * a.incident, gen)
    target = torch.rand(a.batch, 3, generator=gen)

    def step():
        opt.zero_grad(set_to_none=False)
        pred = net(raw)
        with torch.no_grad():
            net(incident)
        loss = ((pred - target) ** 2 / (pred.detach() ** 2 + 0.01)).mean()
        loss.backward()
        opt.step()

    for _ in range(2):
        step()
    times = []
    for _ in range(a.steps):
        t0 = time.perf_counter()
        step()
        times.append(time.perf_counter() - t0)
    times.sort()
    return 1000 * times[len(times) // 2]


if __name__ == "__main__":
    main()
