"""catwalk.bench"""
