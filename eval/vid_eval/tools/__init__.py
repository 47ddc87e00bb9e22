"""vid_eval.tools: files in and out (loaders, tables, run folders) and the workflows built on them."""
