"""Benchmarks and the fuzzer (bench/README.md); a package so that tests can import bench.fuzz."""
