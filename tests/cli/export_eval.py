#!/usr/bin/env python3
"""Evaluates a network of `clradiosity export`'s safetensors file in numpy, from the file alone.

    export_eval.py MODEL.safetensors NETWORK ROWS.f32 ENGINE.f32 [--tolerance T] [--without-grid]

NETWORK is a key of the metadata's "networks" (n_module, i_module, i_module_before_update). ROWS.f32 holds raw input
rows (float32, the metadata's raw_input.columns per row), ENGINE.f32 the engine's outputs for them (float32). Every
step follows the metadata's description (docs/cli.md, "export"): nothing here is read from clradiosity's sources, so
a passing run shows that the file and its metadata suffice. Exit 0 when every output agrees within T relative to
the output's size (|a - b| <= T * max(|b|, rms of the outputs)), 1 otherwise, printing the largest deviation.
--without-grid zeroes the hash grid's features: the comparison must then fail, which shows it sees the grid.
"""
import argparse
import json
import sys

import numpy as np
from safetensors.numpy import load_file
from safetensors import safe_open


def spherical_harmonics(d):
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    xy, xz, yz, x2, y2, z2 = x * y, x * z, y * z, x * x, y * y, z * z
    return np.stack([
        np.full_like(x, 0.28209479177387814),
        -0.48860251190291987 * y,
        0.48860251190291987 * z,
        -0.48860251190291987 * x,
        1.0925484305920792 * xy,
        -1.0925484305920792 * yz,
        0.94617469575755997 * z2 - 0.31539156525251999,
        -1.0925484305920792 * xz,
        0.54627421529603959 * (x2 - y2),
        0.59004358992664352 * y * (-3.0 * x2 + y2),
        2.8906114426405538 * xy * z,
        0.45704579946446572 * y * (1.0 - 5.0 * z2),
        0.3731763325901154 * z * (5.0 * z2 - 3.0),
        0.45704579946446572 * x * (1.0 - 5.0 * z2),
        1.4453057213202769 * z * (x2 - y2),
        0.59004358992664352 * x * (-x2 + 3.0 * y2),
    ], axis=1)


def hash_grid(part, position, tensors):
    lo = np.array(part["bbox_lo"], np.float32)
    hi = np.array(part["bbox_hi"], np.float32)
    inv = (np.float32(1) / (hi - lo)).astype(np.float32)
    p = np.clip((position.astype(np.float32) - lo) * inv, np.float32(0), np.float32(1))  # float32, as the rule says
    features = []
    for level in part["levels"]:
        res, entries = level["resolution"], level["entries"]
        table = tensors[level["tensor"]].astype(np.float64)
        q = p * np.float32(res)
        cell = np.minimum(np.floor(q), np.float32(res - 1))
        t = (q - cell).astype(np.float64)
        cell = cell.astype(np.uint64)
        acc = np.zeros((len(p), table.shape[1]))
        for corner in range(8):
            d = np.array([corner & 1, (corner >> 1) & 1, corner >> 2], np.uint64)
            v = cell + d
            weight = np.prod(np.where(d.astype(bool), t, 1.0 - t), axis=1)
            if level["dense"]:
                side = np.uint64(res + 1)
                index = v[:, 0] + side * (v[:, 1] + side * v[:, 2])
            else:
                h = v[:, 0] ^ (v[:, 1] * np.uint64(2654435761)) ^ (v[:, 2] * np.uint64(805459861))
                index = (h & np.uint64(0xFFFFFFFF)) & np.uint64(entries - 1)
            acc += weight[:, None] * table[index]
        features.append(acc)
    return np.concatenate(features, axis=1)


def evaluate(network, tensors, rows, without_grid=False):
    raw = network["raw_input"]
    columns = np.zeros((len(rows), network["encoded_columns"]))
    for part in network["encoding"]:
        a, b = raw[part["input"]]
        x = rows[:, a:b].astype(np.float64)
        if part["part"] == "hash_grid":
            encoded = hash_grid(part, rows[:, a:b], tensors)
            if without_grid:
                encoded[:] = 0
        elif part["part"] == "spherical_harmonics":
            encoded = spherical_harmonics(x)
        elif part["part"] == "identity":
            encoded = x
        else:
            raise ValueError("unknown encoding part " + part["part"])
        c0, c1 = part["columns"]
        columns[:, c0:c1] = encoded
    h = columns
    for layer in network["mlp"]:
        h = h @ tensors[layer["weight"]].astype(np.float64).T + tensors[layer["bias"]].astype(np.float64)
        h = {"relu": lambda v: np.maximum(v, 0.0), "abs": np.abs, "none": lambda v: v}[layer["activation"]](h)
    h = network["output_scale"] * h
    factor = network.get("albedo_factor")
    if factor:
        a, b = raw[factor["input"]]
        h = h * np.maximum(rows[:, a:b].astype(np.float64), factor["floor"])
    return h


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("network")
    ap.add_argument("rows")
    ap.add_argument("engine")
    ap.add_argument("--tolerance", type=float, default=1e-5)
    ap.add_argument("--without-grid", action="store_true")
    args = ap.parse_args()

    with safe_open(args.model, "np") as f:
        metadata = f.metadata()
    tensors = load_file(args.model)
    network = json.loads(metadata["networks"])[args.network]
    rows = np.fromfile(args.rows, np.float32).reshape(-1, network["raw_input"]["columns"])
    engine = np.fromfile(args.engine, np.float32).astype(np.float64).reshape(len(rows), -1)
    ours = evaluate(network, tensors, rows, args.without_grid)
    scale = max(np.sqrt(np.mean(engine**2)), np.finfo(np.float32).tiny)
    deviation = np.abs(ours - engine) / np.maximum(np.abs(engine), scale)
    worst = np.unravel_index(np.argmax(deviation), deviation.shape)
    print(f"{args.network}: {len(rows)} rows x {engine.shape[1]} outputs, largest relative deviation "
          f"{deviation[worst]:.3g} at row {worst[0]} output {worst[1]} (engine {engine[worst]:.9g}, "
          f"numpy {ours[worst]:.9g}), step {metadata['step']}")
    return 0 if deviation[worst] <= args.tolerance else 1


if __name__ == "__main__":
    sys.exit(main())
