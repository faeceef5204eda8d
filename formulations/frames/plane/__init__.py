"""The plane Frame: its model, assembly, results, member diagrams, sparse
active set and worked examples."""
