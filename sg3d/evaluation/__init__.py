"""Evaluation against a human-judged ground truth: the ground-truth file (`ground_truth`), node
matching (`matching`), edge and question metrics (`edges`, `vqa`), the whole report (`evaluate`)."""
