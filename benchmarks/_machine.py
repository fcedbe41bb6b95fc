"""One line naming the machine a benchmark ran on, for every script here.

``platform.processor()`` says only "x86_64" on Linux, and the wall solver's rate differed 2.6× between
two 2-core VMs that both said so (BENCHMARKS.md, "The block geometry vectorised"): the CPU's model,
family and widest vector instructions are what tell the machines apart.
"""

from __future__ import annotations

import os
import platform


def describe_machine() -> str:
    """E.g. "AMD EPYC (family 26, model 2), AVX-512, x86_64, 2 CPUs" (from /proc/cpuinfo where there is one)."""
    fields: dict[str, str] = {}
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                key, sep, value = line.partition(":")
                if not sep:
                    if fields:
                        break  # the first processor's block is enough
                    continue
                fields.setdefault(key.strip(), value.strip())
    except OSError:
        pass
    name = fields.get("model name") or platform.processor() or platform.machine()
    flags = set(fields.get("flags", "").split())
    vector = "AVX-512" if "avx512f" in flags else ("AVX2" if "avx2" in flags else None)
    parts = [f"{name} (family {fields['cpu family']}, model {fields['model']})" if "cpu family" in fields else name]
    parts += [p for p in (vector, platform.machine(), f"{os.cpu_count()} CPUs") if p]
    return ", ".join(parts)


if __name__ == "__main__":
    print(describe_machine())
