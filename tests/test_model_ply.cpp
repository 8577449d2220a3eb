// tests/test_model_ply.cpp — read_ply (io/ply_reader.cpp). Being written.
