"""catwalk.cloth"""
