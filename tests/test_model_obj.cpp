// tests/test_model_obj.cpp — read_obj (io/obj_reader.cpp). Being written.
